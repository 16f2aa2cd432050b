/// `arbor rays --scene MODEL.obj|builtin:NAME --kind primary|shadow|diffuse|random --count N -o OUT.rays
///  [--seed S] [--view-seed V] [--order tiles|rows] [--light-size F] [--light-distance R] [--from lit|all]
///  [--accel NAME] [--threads N] [--json]`: writes the
/// rays of engine/ray_gen.h to a .rays file (spec/rayfile.md), so any tracer can be fed the same
/// rays. --view-seed moves the camera and the light (engine/ray_views.h: held-out rays).
#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "engine/builtin_scenes.h"
#include "engine/mesh_loader.h"
#include "engine/ray_gen.h"
#include "engine/ray_views.h"
#include "engine/rayfile.h"

#include <cstdio>
#include <iostream>

namespace arbor::app {

namespace {

struct RaysOptions {
    std::string scene, kind = "primary", out, order = "tiles", accel, from = "lit";
    float light_size = 0.0f, light_distance = 0.0f;
    std::size_t count = 0;
    std::uint64_t seed = 1, view_seed = 0;
    int threads = 0;
    bool json = false;
};

/// Upper bound on --count: 2^27 rays are a 4 GiB file.
constexpr std::size_t max_count = std::size_t(1) << 27;

int run_rays(const RaysOptions& o) {
    const auto limit = limit_threads(o.threads);
    const accel::Timer timer;
    engine::Warnings warnings;
    const bool builtin = engine::is_builtin_scene(o.scene);
    const engine::Scene scene = builtin ? engine::make_builtin_scene(o.scene)
                                        : engine::scene_from_mesh(engine::load_mesh(o.scene, warnings), o.scene);
    engine::RayGenConfig cfg;
    cfg.kind = *engine::parse_ray_kind(o.kind);
    cfg.order = *engine::parse_pixel_order(o.order);
    cfg.count = o.count;
    cfg.seed = o.seed;
    cfg.shadow.light_size = o.light_size;
    cfg.shadow.light_distance = o.light_distance;
    cfg.shadow.from_all = o.from == "all";
    // A builtin scene is seen through its own camera (the Cornell box from inside), a model framed.
    engine::RayGenScene gen = engine::ray_gen_scene(scene, builtin);
    if (o.view_seed != 0) engine::place_seeded_view(gen, scene, o.view_seed, builtin);

    std::unique_ptr<accel::Accel> tracer;
    if (cfg.kind == engine::RayKind::shadow || cfg.kind == engine::RayKind::diffuse) {
        tracer = o.accel.empty() ? engine::make_ray_gen_tracer(gen.tris)
                                 : accel::make_accel(resolve_accel(o.accel, accel::trace_job(gen.tris, {}, double(o.count),
                                                                                             accel::Query::closest)).kind,
                                                     gen.tris);
    }
    const std::vector<accel::Ray> rays = engine::generate_rays(gen, cfg, tracer.get());
    engine::write_rays(o.out, rays);

    if (o.json) {
        nlohmann::json j;
        j["file"] = o.out;
        j["scene"] = o.scene;
        j["kind"] = o.kind;
        j["order"] = o.order;
        j["rays"] = rays.size();
        j["seed"] = o.seed;
        j["view_seed"] = o.view_seed;
        if (gen.camera) {
            j["eye"] = {gen.camera->eye.x, gen.camera->eye.y, gen.camera->eye.z};
            j["look_at"] = {gen.camera->look_at.x, gen.camera->look_at.y, gen.camera->look_at.z};
            j["vfov"] = gen.camera->vfov_degrees;
        }
        j["light"] = {gen.light.x, gen.light.y, gen.light.z};
        if (cfg.kind == engine::RayKind::shadow) {
            j["light_size"] = o.light_size;
            j["light_distance"] = o.light_distance;
            j["from"] = o.from;
        }
        j["triangles"] = scene.mesh.triangle_count();
        if (tracer) j["tracer"] = accel::to_string(tracer->kind());
        j["ms"] = timer.ms();
        std::cout << j.dump() << '\n';
        return 0;
    }
    engine::print_warnings(warnings);
    std::printf("%s: %zu %s rays (seed %llu, %s order) in %.1f ms\n", o.out.c_str(), rays.size(), o.kind.c_str(),
                static_cast<unsigned long long>(o.seed), o.order.c_str(), timer.ms());
    return 0;
}

}  // namespace

Run add_rays(CLI::App& cmd) {
    auto o = std::make_shared<RaysOptions>();
    cmd.add_option("--scene", o->scene, "mesh file (OBJ, PLY, STL or glTF 2.0) or builtin:NAME")->required();
    cmd.add_option("--kind", o->kind, "primary, shadow, diffuse or random")
        ->check([](const std::string& v) -> std::string {
            return engine::parse_ray_kind(v) ? std::string()
                                             : "unknown ray kind '" + v + "' (expected primary, shadow, diffuse or random)";
        })
        ->capture_default_str();
    cmd.add_option("--count", o->count, "number of rays")->required()->check(CLI::Range(std::size_t(1), max_count));
    cmd.add_option("-o,--out", o->out, "output .rays file")->required();
    cmd.add_option("--seed", o->seed, "random seed (same seed, same rays)")->capture_default_str();
    cmd.add_option("--view-seed", o->view_seed,
                   "0: the framed camera and the scene's light (the benchmark's rays); else a camera and light "
                   "placed from this seed (held-out rays, engine/ray_views.h)")
        ->capture_default_str();
    cmd.add_option("--order", o->order, "pixel order of primary rays: tiles (8x8, as a renderer) or rows")
        ->check([](const std::string& v) -> std::string {
            return engine::parse_pixel_order(v) ? std::string() : "unknown order '" + v + "' (expected tiles or rows)";
        })
        ->capture_default_str();
    cmd.add_option("--light-size", o->light_size,
                   "shadow rays: 0 = a point light; above 0 = a square area light of this side (times the scene's "
                   "largest extent) facing the scene, one point of it per ray")
        ->check(CLI::Range(0.0f, 100.0f))
        ->capture_default_str();
    cmd.add_option("--light-distance", o->light_distance,
                   "shadow rays: 0 = the light where the view puts it; above 0 = moved to this many bounding radii "
                   "from the scene's centre (below 1: among the geometry, segments of all lengths)")
        ->check(CLI::Range(0.0f, 1000.0f))
        ->capture_default_str();
    cmd.add_option("--from", o->from,
                   "shadow rays: lit = only points facing the light (a renderer's rays); all = every point, those "
                   "facing away through their own surface (mostly occluded sets)")
        ->check(CLI::IsMember({"lit", "all"}))
        ->capture_default_str();
    add_accel_option(cmd, o->accel)->description("structure that traces the primary rays of shadow/diffuse rays");
    add_threads_option(cmd, o->threads);
    cmd.add_flag("--json", o->json, "one JSON object on standard output");
    return [o] { return run_rays(*o); };
}

}  // namespace arbor::app
