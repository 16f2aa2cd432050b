#pragma once
/// Benchmark scenes: the shared models, and procedural scenes that stress the structures in
/// different ways (design.md §5). Everything is deterministic from the arguments.
#include "engine/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arbor::perf {

struct BenchScene {
    std::string name;    ///< unique in a run, e.g. "stadium", "replicated-1e5", "bunny"
    std::string family;  ///< model, stadium, interior, grass, soup, replicated, tiny
    engine::Scene scene; ///< mesh (bounds computed), one light, a camera
    /// Primary rays from scene.camera (a view chosen for the scene) instead of the framed camera.
    bool use_scene_camera = false;
};

/// A model file as a scene: camera framed on its bounds, light above-front (scene_from_mesh).
/// Throws engine::InputError when the file does not load. The name is the file's stem.
BenchScene model_scene(const std::string& obj_path);

/// A dense model (the given one scaled to size 1, or a procedural stand-in when `model` is null)
/// on the floor of a huge, nearly empty room: a floor and four walls 2000 model sizes across made of
/// a few big triangles. The camera looks at the model, so rays meet both scales.
BenchScene teapot_in_stadium(const engine::Mesh* model);

/// A hall (40 x 8 x 24) closed by big triangles, with pillars, partition walls, tables, small
/// objects, roof trusses spanning the whole width and long diagonal braces: many large triangles
/// whose boxes overlap. `detail` scales the number of objects (1 gives ~25k triangles). The
/// camera stands inside, in a corner.
BenchScene architectural_interior(int detail, std::uint64_t seed = 1);

/// A 20 x 20 field of `blades` long thin grass triangles (width ~1/40 of the height, leaning) on a
/// ground quad.
BenchScene grass_field(std::size_t blades, std::uint64_t seed = 1);

/// `count` random triangles in the unit cube, edge length about 2.5 mean spacings (they overlap).
BenchScene triangle_soup(std::size_t count, std::uint64_t seed = 1);

/// A jittered sphere model (5120 triangles) replicated on a grid with random scales and offsets
/// until exactly `triangles` triangles (the last copy is cut short). Named "replicated-1eK" for
/// powers of ten.
BenchScene replicated(std::size_t triangles, std::uint64_t seed = 1);

/// A tiny scene for tests of the benchmark driver (a few hundred triangles).
BenchScene tiny_scene();

/// Memory a scene's mesh needs, in bytes (vertices + indices), to plan big runs.
std::size_t mesh_bytes(const engine::Mesh& m);

}  // namespace arbor::perf
