#pragma once
/// Shared test helpers: ray generators, model paths, hit comparison (rayfile.md tolerance).
#include "accel/interface/accel.h"
#include "engine/mesh.h"

#include <functional>
#include <random>
#include <string>
#include <vector>

namespace arbor::testing {

using accel::Hit;
using accel::Ray;
using accel::Vec3f;

/// Folder of ../shared/scenes (set by CMake). A test that calls it fails (REQUIRE) when the folder
/// is not there: tests on the shared files never pass by skipping them.
std::string shared_scenes_dir();
/// Paths of shared/scenes/models/*.obj, sorted; fails the calling test when there are none.
std::vector<std::string> model_paths();
/// Loads every shared model (model_paths(); fewer than 10 fail the calling test) and calls
/// f(path, mesh) with the path CAPTUREd in the failure messages.
void for_each_shared_mesh(const std::function<void(const std::string& path, const engine::Mesh& mesh)>& f);

/// Rays from points around the bounds towards random points inside them (mostly hitting).
std::vector<Ray> random_rays_into(const accel::Bounds& b, std::size_t n, std::uint32_t seed);
/// Rays with random origins inside the bounds and random directions (incoherent).
std::vector<Ray> random_rays_inside(const accel::Bounds& b, std::size_t n, std::uint32_t seed);
/// A pinhole grid of rays looking at the bounds (coherent, like primary rays).
std::vector<Ray> camera_rays(const accel::Bounds& b, int width, int height);
/// The three kinds above together: n rays into the bounds (seed), n inside (seed + 1) and a square
/// camera grid of about n rays (at least 8 x 8).
std::vector<Ray> three_kinds(const accel::Bounds& b, std::size_t n, std::uint32_t seed);

/// The procedural scene of the oracle tests: a jittered icosphere, a torus through it and a thin
/// slab under both (curved, thin and large flat parts).
engine::Mesh procedural_shapes();
/// Moves the mesh to (offset, -offset, offset / 2) and scales it by `scale` about the origin first
/// (x * scale + offset, ...), then recomputes its bounds: the far-from-origin and tiny placements
/// of the stiff tests.
void place(engine::Mesh& mesh, float offset, float scale);

/// Counts rays whose answers disagree by the rayfile.md rule.
std::size_t count_disagreements(const std::vector<Hit>& a, const std::vector<Hit>& b);
/// For any-hit answers: a hit must be a real hit (t within the ray's range) iff the reference hits.
std::size_t count_occlusion_disagreements(const std::vector<Hit>& any, const std::vector<Hit>& closest);

}  // namespace arbor::testing
