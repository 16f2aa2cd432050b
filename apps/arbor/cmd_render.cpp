/// `arbor render [SCENE] [-o OUT.exr] [--accel NAME] [--leaf-size N] [--sah-bins N] [--spp N] [--width W] [--height H]
///  [--threads N]`.
#include "accel/timer.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "engine/log.h"
#include "engine/obj_loader.h"
#include "engine/renderer.h"

#include <tbb/global_control.h>

#include <cstdio>

namespace arbor::app {

namespace {

struct RenderOptions {
    std::string scene, out = "arbor.exr", accel = "bvh-sah";
    accel::BuildConfig build;
    int spp = 4, width = 640, height = 480, threads = 0, depth = 3;
    bool no_png = false;
};

std::string png_path_for(const std::string& exr) {
    const auto dot = exr.find_last_of('.');
    const auto slash = exr.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return exr + ".png";
    return exr.substr(0, dot) + ".png";
}

int run_render(const RenderOptions& o) {
    const auto limit = limit_threads(o.threads);
    engine::Warnings warnings;
    engine::Scene scene = o.scene.empty() ? engine::make_default_scene()
                                          : engine::scene_from_mesh(engine::load_obj(o.scene, warnings), o.scene);
    engine::print_warnings(warnings);
    std::string reason;
    AutoHints hints;  // about (1 primary + 1 shadow per light + bounces) rays per sample
    hints.budget = double(o.width) * double(o.height) * double(o.spp) * double(1 + scene.lights.size() + o.depth);
    hints.build = o.build;
    const auto kind = resolve_accel(o.accel, scene.mesh.view(), &reason, hints);
    const accel::Timer build_timer;
    const auto structure = accel::make_accel(kind, scene.mesh.view(), o.build);
    const double build_ms = build_timer.ms();

    engine::RenderSettings set;
    set.width = o.width;
    set.height = o.height;
    set.spp = o.spp;
    set.max_depth = o.depth;
    set.progress = true;
    engine::RenderStats stats;
    const engine::Image img = engine::render(scene, *structure, set, &stats);
    engine::write_exr(o.out, img);
    std::string png;
    if (!o.no_png) {
        png = png_path_for(o.out);
        engine::write_png_preview(png, img);
    }
    std::printf("%s: %zu triangles, %s%s%s built in %.1f ms; %dx%d at %d spp rendered in %.3f s, "
                "%.2f Mrays/s (%llu primary, %llu shadow, %llu bounce), %d threads -> %s%s%s\n",
                scene.name.c_str(), scene.mesh.triangle_count(), std::string(accel::to_string(kind)).c_str(),
                reason.empty() ? "" : " (auto: ", reason.empty() ? "" : (reason + ")").c_str(), build_ms, o.width,
                o.height, o.spp, stats.seconds, double(stats.total()) / stats.seconds * 1e-6,
                (unsigned long long)stats.primary, (unsigned long long)stats.shadow, (unsigned long long)stats.bounce,
                active_threads(), o.out.c_str(), png.empty() ? "" : ", ", png.c_str());
    return 0;
}

}  // namespace

Run add_render(CLI::App& cmd) {
    auto o = std::make_shared<RenderOptions>();
    cmd.add_option("SCENE", o->scene, "OBJ file (default: the embedded default scene)");
    cmd.add_option("-o,--output", o->out, "OpenEXR output; a PNG preview is written beside it")->capture_default_str();
    add_accel_option(cmd, o->accel)->capture_default_str();
    add_build_options(cmd, o->build);
    cmd.add_option("--spp", o->spp, "samples per pixel")->check(CLI::Range(1, 1 << 16))->capture_default_str();
    cmd.add_option("--width", o->width, "image width")->check(CLI::Range(1, 1 << 15))->capture_default_str();
    cmd.add_option("--height", o->height, "image height")->check(CLI::Range(1, 1 << 15))->capture_default_str();
    cmd.add_option("--depth", o->depth, "mirror bounces")->check(CLI::Range(0, 64))->capture_default_str();
    cmd.add_flag("--no-png", o->no_png, "do not write the PNG preview");
    add_threads_option(cmd, o->threads);
    return [o] { return run_render(*o); };
}

}  // namespace arbor::app
