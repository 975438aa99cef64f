#include "camera_controller.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace candela::viewer {

glm::vec3 CameraController::forward() const {
    return {-std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_)};
}

void CameraController::reset(const Camera& camera, float distance) {
    lens_ = camera;
    const glm::vec3 eye(camera.world[3]);
    const glm::vec3 f = glm::normalize(-glm::vec3(camera.world[2]));
    pitch_ = std::asin(std::clamp(f.y, -1.0f, 1.0f));
    yaw_ = std::atan2(-f.x, -f.z);
    distance_ = std::max(distance, 1e-4f);
    target_ = eye + f * distance_;
}

void CameraController::frame(const Bounds& bounds) {
    if (bounds.empty()) return;
    target_ = bounds.center();
    const float radius = std::max(0.5f * glm::length(bounds.extent()), 1e-4f);
    const float half_fov = lens_.orthographic ? 0.4f : 0.5f * lens_.yfov;
    distance_ = radius / std::sin(std::max(half_fov, 0.05f)) * 1.05f;
    if (lens_.orthographic) lens_.xmag = lens_.ymag = radius;
}

void CameraController::orbit(float yaw_degrees, float pitch_degrees) {
    const glm::vec3 eye = target_ - forward() * distance_;
    yaw_ += glm::radians(yaw_degrees);
    pitch_ = std::clamp(pitch_ + glm::radians(pitch_degrees), glm::radians(-89.0f), glm::radians(89.0f));
    // Orbit keeps the target; fly keeps the eye.
    if (fly_mode) target_ = eye + forward() * distance_;
}

void CameraController::zoom(float factor) { distance_ = std::clamp(distance_ * factor, 1e-4f, 1e6f); }

void CameraController::pan(float dx, float dy) {
    const glm::vec3 f = forward();
    const glm::vec3 right = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(right, f);
    target_ += (right * dx + up * dy) * distance_;
}

void CameraController::fly(glm::vec3 m) {
    const glm::vec3 f = forward();
    const glm::vec3 right = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(right, f);
    target_ += right * m.x + up * m.y - f * m.z;
}

Camera CameraController::camera() const {
    Camera c = lens_;
    const glm::vec3 eye = target_ - forward() * distance_;
    c.world = glm::inverse(glm::lookAt(eye, target_, glm::vec3(0, 1, 0)));
    return c;
}

}  // namespace candela::viewer
