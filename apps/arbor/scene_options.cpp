#include "apps/arbor/scene_options.h"

#include "apps/arbor/common.h"

#include "engine/builtin_scenes.h"
#include "engine/error.h"
#include "engine/log.h"
#include "engine/mesh_loader.h"
#include "engine/smooth_normals.h"

#include <charconv>
#include <cmath>

namespace arbor::app {

namespace {

std::vector<float> parse_floats(const std::string& option, const std::string& text) {
    std::vector<float> out;
    std::size_t b = 0;
    while (true) {
        const std::size_t e = text.find(',', b);
        const std::string part = text.substr(b, e == std::string::npos ? std::string::npos : e - b);
        float v = 0.0f;
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
        if (part.empty() || ec != std::errc() || end != part.data() + part.size() || !std::isfinite(v))
            throw OptionError(option + ": '" + text + "' is not a list of finite numbers separated by commas");
        out.push_back(v);
        if (e == std::string::npos) break;
        b = e + 1;
    }
    return out;
}

engine::PointLight parse_light(const std::string& l) {
    const auto v = parse_floats("--light", l);
    if (v.size() != 3 && v.size() != 4 && v.size() != 6)
        throw OptionError("--light: expected x,y,z or x,y,z,I or x,y,z,R,G,B, got '" + l + "'");
    engine::Vec3f intensity{1.0f};
    if (v.size() == 4) intensity = engine::Vec3f{v[3]};
    if (v.size() == 6) intensity = {v[3], v[4], v[5]};
    if (intensity.x < 0.0f || intensity.y < 0.0f || intensity.z < 0.0f)
        throw OptionError("--light: intensity must not be negative in '" + l + "'");
    return {{v[0], v[1], v[2]}, intensity};
}

engine::Vec3f parse_background(const std::string& text) {
    const auto v = parse_floats("--background", text);
    if (v.size() != 1 && v.size() != 3) throw OptionError("--background: expected V or R,G,B, got '" + text + "'");
    const engine::Vec3f c = v.size() == 1 ? engine::Vec3f{v[0]} : engine::Vec3f{v[0], v[1], v[2]};
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) throw OptionError("--background: radiance must not be negative");
    return c;
}

}  // namespace

engine::Vec3f parse_vec3(const std::string& option, const std::string& text) {
    const auto v = parse_floats(option, text);
    if (v.size() != 3) throw OptionError(option + ": expected x,y,z (three numbers), got '" + text + "'");
    return {v[0], v[1], v[2]};
}

void add_scene_options(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("SCENE", o.scene, "mesh file (OBJ, PLY, STL, glTF 2.0), or " + engine::builtin_scene_names() + " (default: builtin:default)");
    auto vec3 = [](const char* option) {
        return parse_check(option, [option](const std::string& v) { return parse_vec3(option, v); });
    };
    cmd.add_option("--eye", o.eye, "camera position x,y,z (default: the scene's, or framed on the model)")->check(vec3("--eye"));
    cmd.add_option("--look-at", o.look_at, "point the camera looks at, x,y,z")->check(vec3("--look-at"));
    cmd.add_option("--up", o.up, "camera up vector x,y,z (default 0,1,0)")->check(vec3("--up"));
    cmd.add_option("--fov", o.fov, "vertical field of view in degrees")->check(CLI::Range(0.01f, 179.0f));
    cmd.add_option("--light", o.lights, "add a point light x,y,z[,I | ,R,G,B] (radiant intensity, W/sr; repeatable)")
        ->check(parse_check("--light", parse_light));
    cmd.add_flag("--no-point-lights", o.no_point_lights, "remove the scene's point lights (emissive triangles stay)");
    cmd.add_flag("--smooth", o.smooth, "smooth shading: vertex normals where the file has none (hard edges kept, --crease-angle)");
    cmd.add_option("--crease-angle", o.crease_degrees, "with --smooth: triangles meeting at more than this many degrees keep a hard edge")
        ->check(CLI::Range(0.0f, 180.0f))
        ->capture_default_str();
    cmd.add_option("--background", o.background, "radiance of rays that leave the scene: V or R,G,B")
        ->check(parse_check("--background", parse_background));
}

engine::Scene load_scene(const SceneOptions& o, bool print_warnings, bool with_instances) {
    engine::Scene scene;
    if (o.scene.empty()) {
        scene = engine::make_default_scene();
    } else if (engine::is_builtin_scene(o.scene)) {
        scene = engine::make_builtin_scene(o.scene, with_instances);
    } else {
        engine::Warnings warnings;
        engine::MeshInstances placed;
        engine::Mesh mesh = engine::load_mesh(o.scene, warnings, 0, nullptr, with_instances ? &placed : nullptr);
        scene = engine::scene_from_mesh(std::move(mesh), o.scene, std::move(placed));
        if (print_warnings) engine::print_warnings(warnings);
    }
    // Vertex normals are computed on the meshes as they are held (once per instanced part).
    if (o.smooth) engine::compute_smooth_normals(scene.mesh, o.crease_degrees);
    engine::Camera& cam = scene.camera;
    if (o.fov > 0.0f) cam.vfov_degrees = o.fov;
    // A model framed on its bounds is framed again around --up (Z-up scans come out upright).
    const bool framed = !o.scene.empty() && !engine::is_builtin_scene(o.scene);
    if (framed && !o.up.empty() && o.eye.empty() && o.look_at.empty())
        cam = engine::Camera::framing(engine::scene_bounds(scene), cam.vfov_degrees, parse_vec3("--up", o.up));
    if (!o.eye.empty()) cam.eye = parse_vec3("--eye", o.eye);
    if (!o.look_at.empty()) cam.look_at = parse_vec3("--look-at", o.look_at);
    if (!o.up.empty()) cam.up = parse_vec3("--up", o.up);
    const engine::Vec3f view = cam.look_at - cam.eye;
    if (!(simd::dot(view, view) > 0.0f)) throw OptionError("--look-at: the camera looks at its own position");
    const engine::Vec3f side = simd::cross(view, cam.up);
    if (!(simd::dot(side, side) > 1e-12f * simd::dot(view, view) * simd::dot(cam.up, cam.up)))
        throw OptionError("--up: the up vector is zero or parallel to the viewing direction");
    if (!o.background.empty()) {
        scene.background = parse_background(o.background);
        scene.background_given = true;
    }
    // Lights the user gives replace the ones arbor made; with none given, the made light follows
    // the camera (and the background lights as a sky).
    if (o.no_point_lights || !o.lights.empty()) engine::remove_made_lights(scene);
    else engine::light_from_camera(scene);
    if (o.no_point_lights) scene.lights.clear();
    for (const std::string& l : o.lights) scene.lights.push_back(parse_light(l));
    return scene;
}

}  // namespace arbor::app
