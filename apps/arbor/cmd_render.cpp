/// `arbor render [SCENE] [-o OUT.exr] [--accel NAME] [--leaf-size N] [--sah-bins N] [--spp N] [--width W]
/// [--height H] [--threads N]` plus --integrator, camera, light and layer options. Prints the plan in one line before
/// rendering (--verbose: also what was skipped and why) and a summary line after.
#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "apps/arbor/cluster.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "apps/arbor/render_cost.h"
#include "apps/arbor/render_options.h"
#include "apps/arbor/scene_options.h"
#include "accel/factory/memory_estimate.h"
#include "engine/image_output.h"
#include "engine/memory_budget.h"
#include "engine/render_job.h"
#include "engine/renderer.h"

#include <cstdio>

namespace arbor::app {

namespace {

struct RenderCommand {
    SceneOptions scene;
    RenderOptions render;
    std::string out = "arbor.exr", accel = "bvh-sah";
    accel::BuildConfig build;
    int threads = 0;
    bool no_png = false, verbose = false, quiet = false, mpi = false;
    float exposure = 0.0f;
};

/// Refuses a job whose image, structure and scene would not fit in --max-memory (or the machine's
/// memory), before anything is built or rendered.
void check_render_memory(const RenderCommand& o, const engine::Scene& scene, accel::AccelKind kind,
                         const accel::BuildConfig& build, const engine::RenderPlan& plan) {
    const bool png = !o.no_png || engine::output_format(o.out) == engine::OutputFormat::png;
    const std::uint64_t image = engine::output_image_bytes(o.render.width, o.render.height,
                                                           engine::channel_names(plan.layers).size(), png);
    const std::uint64_t structure = accel::build_memory_estimate(kind, scene.mesh.triangle_count(), build);
    const std::uint64_t budget = engine::memory_budget(build.max_memory);
    if (image + structure > budget)
        throw accel::MemoryLimitError("rendering " + std::to_string(o.render.width) + "x" + std::to_string(o.render.height) +
                                      " needs about " + engine::format_bytes(image + structure) + " (image and layers " +
                                      engine::format_bytes(image) + ", structure " + engine::format_bytes(structure) +
                                      "), more than the " + engine::format_bytes(budget) +
                                      (build.max_memory ? " of --max-memory" : " of memory"));
}

int run_render(const RenderCommand& o) {
    const auto limit = limit_threads(o.threads);
    Cluster* const cluster = Cluster::join(o.mpi);  // mpirun: every rank runs this, rank 0 writes
    const bool writer = !cluster || cluster->root();
    const engine::IntegratorKind integrator = parse_integrator_option(o.render.integrator);
    if (integrator == engine::IntegratorKind::cost && cluster)
        throw OptionError("--integrator cost: not spread over ranks yet; run it without mpirun");
    if (integrator == engine::IntegratorKind::cost)
        return run_cost_render({o.scene, o.render, o.accel, o.build, o.out, o.no_png, o.verbose, o.quiet});
    if (o.accel.find(',') != std::string::npos)
        throw OptionError("--accel: a list of structures needs --integrator cost");
    const engine::RenderSettings base = to_settings(o.render, integrator);
    engine::RenderSettings set = base;
    set.progress = !o.quiet;
    const engine::Scene scene = load_scene(o.scene, writer, true);
    const bool instanced = !scene.placed.empty();
    if (cluster) cluster->require_same(scene, settings_text(set));
    // The renderer traces the SIMD paths (packets and single rays): the scalar layout is not built.
    accel::BuildConfig build = o.build;
    build.layouts = accel::layouts_for(accel::TracePath::best);
    const engine::LightSet lights(scene);
    engine::RenderPlan plan = engine::make_plan(scene, lights, set);
    // --accel auto decides for the plan's ray mix (engine/render_job.h). Under MPI rank 0 alone
    // resolves --accel (a probe measures: ranks could differ); the others take its choice.
    const engine::RenderRays job_rays = engine::render_rays(scene, plan, set);
    accel::AccelPick pick;
    if (instanced) {
        // A structure per placed mesh under a top BVH (engine/mesh_instances.h); auto takes bvh-sah.
        const auto named = accel::parse_accel_kind(o.accel);
        if (!named) throw OptionError("--accel: unknown structure '" + o.accel + "'");
        pick.kind = *named == accel::AccelKind::automatic ? accel::AccelKind::bvh_sah : *named;
        if (*named == accel::AccelKind::automatic)
            pick.reason = "the scene has instances: bvh-sah for each placed mesh, without a probe";
    } else if (writer) {
        pick = resolve_accel(o.accel, engine::render_job(scene, job_rays, build));
    }
    if (cluster) pick.kind = *accel::parse_accel_kind(cluster->root_choice(std::string(accel::to_string(pick.kind))));
    const auto kind = pick.kind;
    for (const std::string& s : accel::skipped_by_build(kind, build)) plan.skipped.push_back("the structure's " + s);
    check_render_memory(o, scene, kind, build, plan);
    const std::string accel_name(accel::to_string(kind));
    std::printf("%s\n", plan.line(accel_name).c_str());
    if (o.verbose) std::printf("%s", plan.skipped_lines().c_str());
    std::fflush(stdout);

    // With auto, its probe may have built the pick already (with these settings).
    const accel::Timer build_timer;
    const bool prebuilt = pick.built != nullptr;
    const auto structure = prebuilt    ? std::move(pick.built)
                           : instanced ? engine::make_instanced_accel(scene.mesh, scene.placed, kind, build)
                                       : accel::make_accel(kind, scene.mesh.view(), build);
    const double build_ms = prebuilt ? structure->stats().build_ms : build_timer.ms();
    engine::RenderStats stats;
    const auto tiles = cluster ? cluster->frame_tiles() : nullptr;
    const engine::Image img = engine::render(scene, lights, plan, *structure, set, &stats, tiles.get());
    std::string written;
    if (writer)
        for (const std::string& f : engine::write_outputs(o.out, img, {!o.no_png, o.exposure}))
            written += (written.empty() ? "" : ", ") + f;
    const std::string ranks = cluster ? cluster->on_ranks() : "";
    const std::string placed = instanced ? " (" + std::to_string(scene.placed.instances.size()) + " instances of " +
                                               std::to_string(scene.mesh.triangle_count()) + " unique triangles)"
                                         : "";
    std::printf(
        "%s: %llu triangles%s, %s%s%s built in %.1f ms; %dx%d, %d spp, %s, rendered in %.3f s with %d thread%s%s -> "
        "%s\n",
        scene.name.c_str(),
        (unsigned long long)(instanced ? scene.placed.effective_triangles() : scene.mesh.triangle_count()),
        placed.c_str(), accel_name.c_str(),
        pick.reason.empty() ? "" : " (auto: ", pick.reason.empty() ? "" : (pick.reason + ")").c_str(), build_ms,
        set.width, set.height, set.spp, std::string(engine::to_string(set.integrator)).c_str(), stats.seconds,
        stats.threads, stats.threads == 1 ? "" : "s", ranks.c_str(), written.c_str());
    std::printf("rays: %s\n", stats.summary().c_str());
    return 0;
}

}  // namespace

Run add_render(CLI::App& cmd) {
    auto o = std::make_shared<RenderCommand>();
    add_scene_options(cmd, o->scene);
    cmd.add_option("-o,--output", o->out, "output image: .exr (all layers, and a PNG preview beside it), .png or .pfm")
        ->check(CLI::Validator([](std::string& v) { return engine::output_problem(v); }, "PATH"))
        ->capture_default_str();
    add_accel_list_option(cmd, o->accel)->capture_default_str();
    add_build_options(cmd, o->build);
    add_render_options(cmd, o->render, false);
    cmd.add_flag("--no-png", o->no_png, "with .exr output: do not write the PNG preview");
    cmd.add_option("--exposure", o->exposure, "PNG output: radiance x 2^EV before the sRGB curve (float outputs keep radiance)")
        ->check(CLI::Range(-64.0f, 64.0f));
    cmd.add_flag("-v,--verbose", o->verbose, "also list what the plan skipped and why");
    cmd.add_flag("-q,--quiet", o->quiet, "no progress bar");
    add_threads_option(cmd, o->threads);
    add_mpi_option(cmd, o->mpi);
    return [o] { return run_render(*o); };
}

}  // namespace arbor::app
