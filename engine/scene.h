#pragma once
/// Scene = mesh + camera + lights. Built-in scenes need no files.
#include "engine/camera.h"
#include "engine/mesh.h"
#include "engine/mesh_instances.h"

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
    /// Parts of `mesh` placed by transforms (engine/mesh_instances.h); empty: the mesh is drawn
    /// as it is. Indexed (MeshInstances::index) by whoever fills it.
    MeshInstances placed;
    Camera camera;
    std::vector<PointLight> lights;
    Vec3f background{0.6f, 0.7f, 0.9f};  ///< radiance of rays that leave the scene
    /// The background also lights diffuse surfaces through shadow rays (a sky; made by
    /// light_from_camera for files without lights). Otherwise only rays that escape see it.
    bool sky_light = false;
    bool background_given = false;  ///< the user set the background (AO's sky takes it, else white)
    bool made_light = false;        ///< lights.front() was made by scene_from_mesh, not given
    std::string lights_note;        ///< which lights were made and where, for the plan line
};

/// The embedded default scene: a ground plane, a jittered sphere, a mirror torus and a box,
/// under one point light (~10k triangles).
Scene make_default_scene();
/// A scene around a loaded mesh: camera framed on its bounds, a grey background, and one point
/// light above-front unless some material emits (then its triangles are the lights). The ray
/// generator and the benchmarks use this light; `arbor render` replaces it (light_from_camera).
/// With `placed` (indexed) the camera and light are fitted to the placed triangles' box.
Scene scene_from_mesh(Mesh mesh, std::string name, MeshInstances placed = {});
/// Replaces the scene's instances by the flattened mesh (flatten()), for the commands that do not
/// trace instances; InputError naming `what` when the copy would need more than half the memory.
void flatten_instances(Scene& scene, const std::string& what);
/// The box of what the scene draws: the mesh's, or with instances the placed triangles'.
Bounds scene_bounds(const Scene& scene);

/// For a scene whose only light is the one scene_from_mesh made: a key light that follows the
/// camera (above and to the left of the eye, irradiance 2 where the camera looks) plus the
/// background as a dim sky lighting from every direction, so that any viewpoint sees the model
/// lit. Call after the camera is final. Records what it made in lights_note.
void light_from_camera(Scene& scene);
/// Removes the lights scene_from_mesh or light_from_camera made (when the user gives lights).
void remove_made_lights(Scene& scene);

}  // namespace arbor::engine
