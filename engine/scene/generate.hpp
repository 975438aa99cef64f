#pragma once
// Scenes made in code for benchmarks and stress tests.
#include <cstddef>
#include <string>

#include "scene/scene.hpp"

namespace candela {

// An axis-aligned box's six faces (flat normals, counter-clockwise seen from outside) added to `p`.
void append_box(Primitive& p, glm::vec3 lo, glm::vec3 hi);
// A quad with corner `o` and edges `eu`, `ev`, facing cross(eu, ev), added to `p`.
void append_quad(Primitive& p, glm::vec3 o, glm::vec3 eu, glm::vec3 ev);
// A UV sphere of radius r around the origin with exact normals; rings x 2 rings quads (no UVs).
Primitive uv_sphere(float r, int rings);
// A rough (0.9) dielectric Lambert-like material of `colour`, for the generated scenes.
Material lambert_material(const char* name, glm::vec3 colour);
// Scenes built in code (generators, tests): a mesh of one primitive (its bounds computed), a light
// or a camera on a new root node; each returns the node's index. The light shines along the
// node's -Z; add_sun adds a directional light named "sun" shining from the direction `to_light`;
// add_look_at_camera places a perspective camera at `eye` looking at `target` and returns it.
int add_mesh_node(Scene& scene, const std::string& name, Primitive primitive, const glm::mat4& local = glm::mat4(1.0f));
int add_light_node(Scene& scene, const Light& light, const glm::mat4& local);
int add_sun(Scene& scene, glm::vec3 to_light, float intensity);
Camera& add_look_at_camera(Scene& scene, glm::vec3 eye, glm::vec3 target, float yfov = 0.8f, glm::vec3 up = glm::vec3(0, 1, 0),
                           const char* name = "view");

// A bumpy sphere (a UV sphere with a deterministic radial displacement) of about `triangles`
// triangles on a ground quad, one white Lambert material, a directional light, a framing camera.
Scene make_bumpy_sphere_scene(std::size_t triangles);

// The forward-vs-deferred benchmark scene: a 20 x 20 floor with a grid of boxes, `lights` point
// lights of range 3 scattered over it (deterministic colours and positions), a little ambient
// light and a camera looking over it. `bounded` (generated:lights-bounded:N): the range shrinks as
// 3 * sqrt(16 / N) from 16 lights on, and the heights with it, so that a point of the floor is
// reached by about as many lights at any N (about one): the scene on which the cost of many lights
// should follow what they add, not their number.
Scene make_many_lights_scene(int lights, bool bounded = false);
// generated:street:N: N point lamps without a range (the glTF default), 20 m apart and 2 m above a
// road 20 m wide, seen along the road: the scene of lights.cutoff, where each lamp lights its
// stretch of road and the far ones add nearly nothing.
Scene make_street_scene(int lamps);
// generated:emitters:N: the floor and boxes of generated:lights-bounded:N lit by N emissive
// 0.2 m squares facing down instead of point lights, at the same places and heights, each with
// the power of one of its lights (2 W/sr straight down, times 16 / N from 16 on, as the heights
// shrink): the scene of many small emitters (arealight.far_field).
Scene make_emitters_scene(int emitters);

// generated:dof (generate_dof.cpp): the depth-of-field scene, a thin-lens camera focused on a
// subject between a near and a far out-of-focus object, over a checkered floor and back wall.
Scene make_dof_scene();

// generated:edges (generate_edges.cpp): the anti-aliasing scene, thin and high-contrast edges (a
// slanted checkerboard, sub-pixel wires, a MASK fence, a tilted box) on a white wall under a
// point light at the camera.
Scene make_edges_scene();

// generated:materials (generate_materials.cpp): the material extensions' layers side by side, a
// sphere each (plain, clearcoat, sheen, anisotropic metal, iridescent, clearcoat over sheen) on
// a floor under a sun and a sky: the scene of `bench accuracy`'s material_layers section.
Scene make_materials_scene();

// generated:motion (generate_motion.cpp): the motion-blur scene, animation 0 (LINEAR samplers,
// [0, 1] s) slides a banded box across the view and spins another over a checkered floor and
// back wall under a directional light.
Scene make_motion_scene();

// generated:skinned:N (generate_skinned.cpp): a tube of about N triangles skinned to a chain of 8
// bones (two influences per vertex) that sway in a travelling wave (animation 0, 2 s), over a
// floor under a directional light: the animation cost benchmark at any size.
Scene make_skinned_scene(std::size_t triangles);

// generated:random:SEED (generate_random.cpp): a random scene for the statistical property tests
// (tests/unit/test_random_scenes.cpp), the same on every platform for a seed: a closed room, an
// open floor with a back wall or no room; boxes, spheres and thin walls of diffuse, glossy,
// metal and glass materials; point, spot, directional, quad-emitter and environment light; a
// camera inside or outside the room; every length scaled by a factor from 0.1 to 20.
Scene make_random_scene(std::uint32_t seed);

}  // namespace candela
