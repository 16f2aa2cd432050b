#pragma once
/// Scenes that need no files, selected by name with a `builtin:NAME` scene argument:
///   builtin:default        the embedded default scene (scene.h)
///   builtin:cornell        a Cornell box lit by an area light, with the Stanford bunny from
///                          ../shared/scenes/models when present (else a procedural blob) and a
///                          mirror sphere
///   builtin:scaling[:N]    N x N copies (default 6) of the bunny (or a 82k-triangle procedural
///                          blob) on a ground plane: millions of triangles
///   builtin:field[:N]      N x N instances (default 100) of four procedural models of 82k to
///                          328k triangles on a ground plane: 0.7 million unique triangles
///                          placed 1.75 billion times (engine/mesh_instances.h)
#include "engine/scene.h"

#include <string>

namespace arbor::engine {

/// True when `arg` names a built-in scene ("builtin:..."), whether or not the name is known.
bool is_builtin_scene(const std::string& arg);
/// Makes the built-in scene `arg` ("builtin:NAME[:N]"); InputError naming the argument for an
/// unknown name or a bad N. A scene with instances keeps them only `with_instances`; otherwise
/// it is flattened (flatten_instances: an InputError when that does not fit in memory).
Scene make_builtin_scene(const std::string& arg, bool with_instances = false);
/// "builtin:default, builtin:cornell, builtin:scaling[:N], builtin:field[:N]", for messages.
std::string builtin_scene_names();

/// The folder of the shared test models: $ARBOR_SHARED_SCENES/models when that variable is set,
/// else the folder configured at build time; the result may not exist.
std::string shared_models_dir();

Scene make_cornell_scene();
Scene make_scaling_scene(int copies_per_side);
Scene make_field_scene(int per_side);

/// Scales `mesh` uniformly so that its height (y extent) is `height`, centres it on x and z at
/// (cx, cz), and stands it on y = floor.
void place_on_floor(Mesh& mesh, float height, float cx, float cz, float floor);

}  // namespace arbor::engine
