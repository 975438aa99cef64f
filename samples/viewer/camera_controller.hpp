#pragma once
// Orbit and fly cameras for the viewer. Orbit: drag to turn about a target, scroll to move in
// and out, shift-drag (or middle drag) to pan. Fly: WASD (+QE down/up) moves, drag turns.
#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace candela::viewer {

class CameraController {
public:
    // Starts at `camera` (its lens is kept), orbiting a point `distance` ahead of it.
    void reset(const Camera& camera, float distance);
    // Frames the bounds: target at their centre, the whole sphere around them in view.
    void frame(const Bounds& bounds);

    void orbit(float yaw_degrees, float pitch_degrees);  // turn (orbit: about the target; fly: in place)
    void zoom(float factor);                              // orbit: distance *= factor
    void pan(float dx, float dy);                         // in units of the distance
    void fly(glm::vec3 local_move);                       // camera-space move (x right, y up, -z ahead), world units
    void shift(const glm::vec3& by) { target_ -= by; }    // the scene's origin moved by `by`: the same view
    bool fly_mode = false;

    Camera camera() const;  // the current camera (world matrix from position and angles)
    float distance() const { return distance_; }

private:
    glm::vec3 forward() const;
    Camera lens_;
    glm::vec3 target_{0.0f};
    float yaw_ = 0.0f, pitch_ = 0.0f;  // radians; yaw 0 looks along -Z
    float distance_ = 1.0f;
};

}  // namespace candela::viewer
