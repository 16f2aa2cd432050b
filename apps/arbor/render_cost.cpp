#include "apps/arbor/render_cost.h"

#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "apps/arbor/common.h"
#include "engine/render_job.h"
#include "engine/cost_sheet.h"
#include "engine/image.h"
#include "engine/image_output.h"
#include "engine/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace arbor::app {

namespace {

/// The structures' images laid side by side, without gaps: one EXR with the layers nodes and tris.
engine::Image side_by_side(const std::vector<engine::Image>& images) {
    const int w = images[0].width, h = images[0].height;
    engine::Image out(w * int(images.size()), h, images[0].names);
    for (std::size_t i = 0; i < images.size(); ++i)
        for (std::size_t c = 0; c < out.names.size(); ++c)
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) out.at(int(c), int(i) * w + x, y) = images[i].at(int(c), x, y);
    return out;
}

/// Renders timed for the labels' speed figure (the median is shown, with half the range as its
/// accuracy).
constexpr int timing_rounds = 5;

struct CameraSpeed {
    double median = 0, min = 0, max = 0;  ///< Mrays/s of camera rays on the renderer's path
    /// Half the range, relative to the median: the +-x shown on the label.
    double spread() const { return median > 0 ? 0.5 * (max - min) / median : 0.0; }
};

/// Each structure's camera rays, traced as `arbor render --integrator primary` traces them (its
/// SIMD paths; no counting), timed inside the structure over timing_rounds renders, the structures
/// taking turns (the machine's drift hits them alike).
std::vector<CameraSpeed> time_camera_rays(const engine::Scene& scene, const engine::LightSet& lights,
                                          const std::vector<std::unique_ptr<accel::Accel>>& structures,
                                          engine::RenderSettings set) {
    // At least about 2^20 camera rays per render (more samples of the same pixels), so that a timed
    // render lasts longer than a time slice of this machine's scheduler.
    const double rays = double(set.width) * double(set.height) * double(set.spp);
    set.spp *= int(std::clamp(std::ceil(double(1 << 20) / rays), 1.0, 64.0));
    set.integrator = engine::IntegratorKind::primary;
    set.layers = engine::Layers{};
    set.progress = false;
    const engine::RenderPlan plan = engine::make_plan(scene, lights, set);
    std::vector<std::vector<double>> rates(structures.size());
    for (int round = 0; round < timing_rounds; ++round)
        for (std::size_t i = 0; i < structures.size(); ++i) {
            engine::RenderStats stats;
            engine::render(scene, lights, plan, *structures[i], set, &stats);
            const auto k = std::size_t(engine::RenderRayKind::primary);
            const double per_thread = stats.trace_seconds[k] / double(std::max(1, stats.threads));
            rates[i].push_back(per_thread > 0 ? double(stats.rays[k]) / per_thread * 1e-6 : 0.0);
        }
    std::vector<CameraSpeed> out;
    for (std::vector<double>& r : rates) {
        std::sort(r.begin(), r.end());
        out.push_back({r[r.size() / 2], r.front(), r.back()});
    }
    return out;
}

}  // namespace

int run_cost_render(const CostRenderOptions& o) {
    if (!o.render.layers.empty()) throw OptionError("--layers: the cost integrator writes the layers nodes and tris only");
    const auto format = engine::output_format(o.out);
    if (format == engine::OutputFormat::pfm)
        throw OptionError("-o: '" + o.out + "': the cost integrator writes .exr (layers nodes and tris, and the picture "
                          "beside it) or .png (the picture)");
    engine::RenderSettings set = to_settings(o.render, engine::IntegratorKind::cost);
    set.progress = !o.quiet;
    const engine::Scene scene = load_scene(o.scene);
    // The counting loop walks the scalar reference layout; the timed camera rays take the
    // renderer's SIMD paths: both are built (the BVHs then without the SIMD leaf floor).
    accel::BuildConfig build = o.build;
    build.layouts = accel::Layouts::all;
    const engine::LightSet lights(scene);
    const engine::RenderPlan plan = engine::make_plan(scene, lights, set);
    // --accel auto decides for the camera rays this render traces (engine/render_job.h).
    const engine::RenderRays job_rays = engine::render_rays(scene, plan, set);
    std::vector<accel::AccelKind> kinds;
    std::vector<std::string> names, reasons;
    for (const std::string& n : split_list(o.accels)) {
        accel::AccelPick pick = resolve_accel(n, engine::render_job(scene, job_rays, build));
        kinds.push_back(pick.kind);
        names.emplace_back(accel::to_string(kinds.back()));
        reasons.push_back(std::move(pick.reason));
    }
    std::string joined;
    for (const std::string& n : names) joined += (joined.empty() ? "" : ",") + n;
    std::printf("%s\n", plan.line(joined).c_str());
    if (o.verbose) std::printf("%s", plan.skipped_lines().c_str());
    std::fflush(stdout);

    std::vector<std::unique_ptr<accel::Accel>> structures;
    std::vector<engine::Image> images;
    double seconds = 0.0;
    int threads = 1;
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        const accel::Timer build_timer;
        structures.push_back(accel::make_accel(kinds[i], scene.mesh.view(), build));
        const double build_ms = build_timer.ms();
        engine::RenderStats stats;
        images.push_back(engine::render(scene, lights, plan, *structures.back(), set, &stats));
        seconds += stats.seconds;
        threads = stats.threads;
        const engine::CostSummary s = engine::summarize_cost(images.back());
        std::printf("%s%s%s: built in %.1f ms; per camera ray: %.4g nodes visited (max %.4g), %.4g triangles tested (max %.4g)\n",
                    names[i].c_str(), reasons[i].empty() ? "" : " (auto: ", reasons[i].empty() ? "" : (reasons[i] + ")").c_str(),
                    build_ms, s.mean_nodes, s.max_nodes, s.mean_tris, s.max_tris);
        std::fflush(stdout);
    }
    const std::vector<CameraSpeed> speed = time_camera_rays(scene, lights, structures, set);
    for (std::size_t i = 0; i < kinds.size(); ++i)
        std::printf("%s: camera rays at %.3g Mrays/s (median of %d renders, interleaved; range %.3g-%.3g)\n", names[i].c_str(),
                    speed[i].median, timing_rounds, speed[i].min, speed[i].max);

    std::vector<engine::CostPanel> panels;
    for (std::size_t i = 0; i < images.size(); ++i) panels.push_back({names[i], &images[i], speed[i].median, speed[i].spread()});
    std::string exr, png;
    if (format == engine::OutputFormat::png) {
        png = o.out;
    } else {
        exr = o.out;
        engine::write_exr(exr, images.size() == 1 ? images[0] : side_by_side(images));
        if (!o.no_png) png = std::filesystem::path(o.out).replace_extension(".png").string();
    }
    if (!png.empty()) engine::write_png(png, engine::cost_sheet(panels));
    std::printf("%s: %zu triangles; %dx%d, %d spp, cost, %zu structure%s rendered in %.3f s with %d threads -> %s%s%s\n",
                scene.name.c_str(), scene.mesh.triangle_count(), set.width, set.height, set.spp, kinds.size(),
                kinds.size() == 1 ? "" : "s", seconds, threads, exr.c_str(), !exr.empty() && !png.empty() ? ", " : "",
                png.c_str());
    return 0;
}

}  // namespace arbor::app
