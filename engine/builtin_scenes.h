#pragma once
/// Scenes that need no files, selected by name with a `builtin:NAME` scene argument:
///   builtin:default        the embedded default scene (scene.h)
///   builtin:cornell        a Cornell box lit by an area light, with the Stanford bunny from
///                          ../shared/scenes/models when present (else a procedural blob) and a
///                          mirror sphere
///   builtin:scaling[:N]    N x N copies (default 6) of the bunny (or a 82k-triangle procedural
///                          blob) on a ground plane: millions of triangles
#include "engine/scene.h"

#include <string>

namespace arbor::engine {

/// True when `arg` names a built-in scene ("builtin:..."), whether or not the name is known.
bool is_builtin_scene(const std::string& arg);
/// Makes the built-in scene `arg` ("builtin:NAME[:N]"); InputError naming the argument for an
/// unknown name or a bad N.
Scene make_builtin_scene(const std::string& arg);
/// "builtin:default, builtin:cornell, builtin:scaling[:N]", for messages.
std::string builtin_scene_names();

/// The folder of the shared test models: $ARBOR_SHARED_SCENES/models when that variable is set,
/// else the folder configured at build time; the result may not exist.
std::string shared_models_dir();

Scene make_cornell_scene();
Scene make_scaling_scene(int copies_per_side);

/// Scales `mesh` uniformly so that its height (y extent) is `height`, centres it on x and z at
/// (cx, cz), and stands it on y = floor.
void place_on_floor(Mesh& mesh, float height, float cx, float cz, float floor);

}  // namespace arbor::engine
