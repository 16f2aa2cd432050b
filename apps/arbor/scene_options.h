#pragma once
/// The scene and camera options shared by `arbor render` and `arbor converge`: the SCENE argument
/// (a mesh file or builtin:NAME), the camera (--eye --look-at --up --fov, else the scene's own or
/// one framed on the model, around --up), point lights (--light; without any, a model gets a key
/// light that follows the camera and a dim sky), --no-point-lights, --background, --smooth.
#include "engine/scene.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace arbor::app {

struct SceneOptions {
    std::string scene;  ///< empty: builtin:default
    std::string eye, look_at, up;
    float fov = 0.0f;  ///< 0: the scene's
    std::vector<std::string> lights;
    bool no_point_lights = false;
    std::string background;
    bool smooth = false;          ///< compute vertex normals where the file has none
    float crease_degrees = 60.0f;
};

/// Registers SCENE and the camera/light options on `cmd`.
void add_scene_options(CLI::App& cmd, SceneOptions& o);

/// Loads or makes the scene and applies the options. InputError naming the option or file on
/// bad input (unparsable vectors, eye == look-at, up parallel to the view, fov outside (0, 180)).
/// `with_instances`: a glTF file that repeats meshes and a built-in scene of instances keep them
/// (engine/mesh_instances.h; for commands that trace instances); otherwise they are flattened.
engine::Scene load_scene(const SceneOptions& o, bool print_warnings = true, bool with_instances = false);

/// Parses "x,y,z" for option `option` (one-line InputError otherwise).
engine::Vec3f parse_vec3(const std::string& option, const std::string& text);

}  // namespace arbor::app
