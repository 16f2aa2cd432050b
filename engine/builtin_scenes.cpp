#include "engine/builtin_scenes.h"

#include "engine/error.h"
#include "engine/log.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"

#include <charconv>
#include <cstdlib>
#include <filesystem>

#ifndef ARBOR_DEFAULT_SHARED_SCENES
#define ARBOR_DEFAULT_SHARED_SCENES "../shared/scenes"
#endif

namespace arbor::engine {

bool is_builtin_scene(const std::string& arg) { return arg.rfind("builtin:", 0) == 0; }

std::string builtin_scene_names() { return "builtin:default, builtin:cornell, builtin:scaling[:N], builtin:field[:N]"; }

std::string shared_models_dir() {
    const char* env = std::getenv("ARBOR_SHARED_SCENES");
    return std::string(env && *env ? env : ARBOR_DEFAULT_SHARED_SCENES) + "/models";
}

namespace {

/// N of "NAME:N" (from 1 to `most`); InputError naming `arg` otherwise.
int copies_of(const std::string& arg, const std::string& n, int most) {
    int copies = 0;
    const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), copies);
    if (ec != std::errc() || end != n.data() + n.size() || copies < 1 || copies > most)
        throw InputError(arg + ": the number of copies per side must be an integer from 1 to " + std::to_string(most));
    return copies;
}

Scene make_named(const std::string& arg) {
    const std::string name = arg.substr(std::string("builtin:").size());
    if (name == "default") return make_default_scene();
    if (name == "cornell") return make_cornell_scene();
    if (name == "scaling") return make_scaling_scene(6);
    if (name.rfind("scaling:", 0) == 0) return make_scaling_scene(copies_of(arg, name.substr(8), 64));
    if (name == "field") return make_field_scene(100);
    // 120 x 120 places 2.5 billion triangles: the global numbers stay below 2^32.
    if (name.rfind("field:", 0) == 0) return make_field_scene(copies_of(arg, name.substr(6), 120));
    throw InputError(arg + ": unknown built-in scene (expected one of " + builtin_scene_names() + ")");
}

}  // namespace

Scene make_builtin_scene(const std::string& arg, bool with_instances) {
    Scene s = make_named(arg);
    if (!with_instances) flatten_instances(s, arg);
    return s;
}

void place_on_floor(Mesh& mesh, float height, float cx, float cz, float floor) {
    mesh.compute_bounds();
    const Vec3f lo = mesh.bounds.lo, c = mesh.bounds.center();
    const float ext = mesh.bounds.extent().y;
    const float s = ext > 0.0f ? height / ext : 1.0f;
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        mesh.x[i] = (mesh.x[i] - c.x) * s + cx;
        mesh.y[i] = (mesh.y[i] - lo.y) * s + floor;
        mesh.z[i] = (mesh.z[i] - c.z) * s + cz;
    }
    mesh.compute_bounds();
}

}  // namespace arbor::engine
