#pragma once
/// Scene = mesh + camera + lights. Built-in scenes need no files.
#include "engine/camera.h"
#include "engine/mesh.h"

#include <string>
#include <vector>

namespace arbor::engine {

struct PointLight {
    Vec3f position;
    Vec3f intensity;  ///< radiant intensity (W/sr); irradiance falls off as 1/d^2
};

struct Scene {
    std::string name;
    Mesh mesh;
    Camera camera;
    std::vector<PointLight> lights;
    Vec3f background{0.6f, 0.7f, 0.9f};  ///< radiance of rays that leave the scene
};

/// The embedded default scene: a ground plane, a jittered sphere, a mirror torus and a box,
/// under one point light (~10k triangles).
Scene make_default_scene();
/// A scene around a loaded mesh: camera framed on its bounds, a grey background, and one point
/// light above-front unless some material emits (then its triangles are the lights).
Scene scene_from_mesh(Mesh mesh, std::string name);

}  // namespace arbor::engine
