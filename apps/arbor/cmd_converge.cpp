/// `arbor converge [SCENE] --out DIR [--max-spp N] [--reference REF.exr] [--accel NAME[,NAME…]]`
/// (spec/cli.md), plus --integrator NAME[,NAME…]: error against run time. Renders (or reads) a
/// reference per integrator, then renders at 1, 2, 4, … spp up to --max-spp with every structure
/// and integrator, timing each, and writes DIR/converge.csv and the plot DIR/converge.png.
#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "apps/arbor/cluster.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "apps/arbor/render_options.h"
#include "apps/arbor/scene_options.h"
#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/image.h"
#include "engine/image_metrics.h"
#include "engine/render_job.h"
#include "engine/renderer.h"
#include "plot_script.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sys/wait.h>

namespace arbor::app {

namespace {

struct ConvergeCommand {
    SceneOptions scene;
    RenderOptions render;
    std::string out_dir, reference, accels = "bvh-sah", integrators = "direct";
    int max_spp = 64, ref_spp = 0, repeat = 1, threads = 0;
    bool no_plot = false, verbose = false, mpi = false;
    bool size_given = false;
    accel::BuildConfig build;
};

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// Writes the plot script beside the CSV and runs it. Returns a note for the user; never throws
/// for a missing python or matplotlib (the CSV is the result, the plot a convenience).
std::string make_plot(const std::filesystem::path& dir, const std::string& title) {
    const auto script = dir / "plot_converge.py", csv = dir / "converge.csv", png = dir / "converge.png";
    const auto log = dir / "plot.log";
    engine::write_file_atomic(script.string(), plot_converge_py);
    const char* env = std::getenv("ARBOR_PYTHON");
    std::string python = env && *env ? env : (std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3");
    const std::string cmd = shell_quote(python) + " " + shell_quote(script.string()) + " " + shell_quote(csv.string()) +
                            " " + shell_quote(png.string()) + " " + shell_quote(title) + " >" +
                            shell_quote(log.string()) + " 2>&1";
    const int status = std::system(cmd.c_str());
    const int code = status == -1 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    if (code == 0) return "plot: " + png.string();
    if (code == 127 || code == 126) return "plot skipped: no Python interpreter '" + python + "' (install python3 and python3-matplotlib, then run " + script.string() + ")";
    if (code == 3) return "plot skipped: matplotlib is missing (install python3-matplotlib, then run " + script.string() + ")";
    return "plot skipped: the plot script failed (exit " + std::to_string(code) + "), see " + log.string();
}

/// The rays a converge run renders with one structure, per integrator: 1 + 2 + 4 + ... + max_spp
/// samples per pixel, each --repeat times, and the reference when this structure renders it.
std::vector<engine::RenderRays> converge_rays(const ConvergeCommand& o, const engine::Scene& scene,
                                              const engine::LightSet& lights,
                                              const std::vector<engine::IntegratorKind>& integrators, bool renders_reference) {
    double spp_total = 0.0;
    for (int spp = 1; spp <= o.max_spp; spp *= 2) {
        spp_total += double(spp) * double(o.repeat);
        if (spp > o.max_spp / 2) break;
    }
    std::vector<engine::RenderRays> out;
    for (const engine::IntegratorKind k : integrators) {
        engine::RenderSettings set = to_settings(o.render, k);
        set.spp = 1;
        const double ref = renders_reference && o.reference.empty() ? double(o.ref_spp > 0 ? o.ref_spp : 8 * o.max_spp) : 0.0;
        out.push_back(engine::render_rays(scene, engine::make_plan(scene, lights, set), set, spp_total + ref));
    }
    return out;
}

/// --accel NAME[,NAME...] as structure kinds (OptionError naming the option otherwise).
std::vector<accel::AccelKind> parse_accels(const std::string& accels) {
    std::vector<accel::AccelKind> kinds;
    for (const std::string& name : split_list(accels)) {
        const auto k = accel::parse_accel_kind(name);
        if (!k) throw OptionError("--accel: unknown structure '" + name + "' (expected one of " + accel::accel_kind_names() + ")");
        kinds.push_back(*k);
    }
    return kinds;
}

/// --integrator NAME[,NAME...]; the cost integrator makes no image to converge.
std::vector<engine::IntegratorKind> parse_integrators(const std::string& names) {
    std::vector<engine::IntegratorKind> integrators;
    for (const std::string& name : split_list(names)) integrators.push_back(parse_integrator_option(name));
    for (engine::IntegratorKind k : integrators)
        if (k == engine::IntegratorKind::cost)
            throw OptionError("--integrator: cost makes no image to converge (use arbor render --integrator cost)");
    return integrators;
}

/// The image of --reference (empty without it); without --width/--height the renders take its
/// size, otherwise its size must be theirs.
engine::Image read_reference(ConvergeCommand& o) {
    engine::Image given;
    if (o.reference.empty()) return given;
    given = engine::read_exr(o.reference);
    if (given.channel("R") < 0 || given.channel("G") < 0 || given.channel("B") < 0)
        throw engine::InputError(o.reference + ": no R, G, B channels");
    if (!o.size_given) o.render.width = given.width, o.render.height = given.height;
    if (given.width != o.render.width || given.height != o.render.height)
        throw OptionError("--reference: " + o.reference + " is " + std::to_string(given.width) + "x" +
                          std::to_string(given.height) + " but the renders are " + std::to_string(o.render.width) + "x" +
                          std::to_string(o.render.height));
    return given;
}

/// What every step of one converge run shares.
struct ConvergeRun {
    const ConvergeCommand& o;
    const engine::Scene& scene;
    const engine::LightSet& lights;
    const std::vector<engine::IntegratorKind>& integrators;
    Cluster* cluster;              ///< the MPI job, if any
    engine::TileSource* tiles;     ///< the frame's tiles spread over the ranks (nullptr: all here)
    bool writer;                   ///< this process writes (rank 0, or no MPI)
    std::filesystem::path dir;
    accel::BuildConfig build;
};

/// The structure of kind `kind` (`first`: the first of --accel, which renders the references).
/// --accel auto decides once for everything this structure renders here (converge_rays). Under MPI
/// rank 0 alone resolves it (a probe measures: ranks could differ).
accel::AccelPick pick_structure(const ConvergeRun& run, accel::AccelKind kind, bool first) {
    accel::AccelPick pick;
    pick.kind = kind;
    if (run.writer) {
        std::vector<engine::RenderRays> job_rays;
        if (kind == accel::AccelKind::automatic) job_rays = converge_rays(run.o, run.scene, run.lights, run.integrators, first);
        accel::AutoJob job;
        job.tris = run.scene.mesh.view();
        job.build = run.build;
        for (const engine::RenderRays& r : job_rays) job.groups.insert(job.groups.end(), r.groups.begin(), r.groups.end());
        pick = accel::pick_accel(kind, job);
        if (!pick.reason.empty()) std::printf("auto: %s\n", pick.reason.c_str());
    }
    if (run.cluster) pick.kind = *accel::parse_accel_kind(run.cluster->root_choice(std::string(accel::to_string(pick.kind))));
    return pick;
}

/// Renders the reference of integrator settings `set` at `ref_spp` with `structure`, and writes it
/// (EXR and PNG) into the output folder. The reference uses other random streams than the renders
/// it judges.
engine::Image render_reference(const ConvergeRun& run, const engine::RenderSettings& set, int ref_spp,
                               const accel::Accel& structure, accel::AccelKind kind, const std::string& iname) {
    engine::RenderSettings ref = set;
    ref.spp = ref_spp;
    ref.seed = set.seed + 0x9E3779B9u;
    ref.progress = true;
    const engine::RenderPlan plan = engine::make_plan(run.scene, run.lights, ref);
    std::printf("reference: %s\n", plan.line(std::string(accel::to_string(kind))).c_str());
    std::fflush(stdout);
    engine::Image image = engine::render(run.scene, run.lights, plan, structure, ref, nullptr, run.tiles);
    if (run.writer) {
        engine::write_exr((run.dir / ("reference-" + iname + ".exr")).string(), image);
        engine::write_png_preview((run.dir / ("reference-" + iname + ".png")).string(), image);
    }
    return image;
}

/// Renders at 1, 2, 4, ... spp up to --max-spp, each --repeat times (the median time counts),
/// judges each image against `reference`, and adds one CSV row and one printed line per render.
void render_series(const ConvergeRun& run, engine::RenderSettings set, const accel::Accel& structure,
                   accel::AccelKind kind, double build_ms, const engine::Image& reference, const std::string& iname,
                   std::string& csv) {
    const ConvergeCommand& o = run.o;
    for (int spp = 1; spp <= o.max_spp; spp *= 2) {
        set.spp = spp;
        const engine::RenderPlan plan = engine::make_plan(run.scene, run.lights, set);
        if (spp == 1 && o.verbose) std::printf("%s\n%s", plan.line(std::string(accel::to_string(kind))).c_str(), plan.skipped_lines().c_str());
        std::vector<double> times;
        engine::Image img;
        engine::RenderStats stats;
        for (int r = 0; r < o.repeat; ++r) {
            img = engine::render(run.scene, run.lights, plan, structure, set, &stats, run.tiles);
            times.push_back(stats.seconds);
        }
        std::sort(times.begin(), times.end());
        const double seconds = times[times.size() / 2];
        // Other ranks hold only their own tiles: rank 0 alone judges the image.
        const engine::ImageError err =
            run.writer ? engine::compare_rgb(img, reference, o.reference.empty() ? "reference" : o.reference)
                       : engine::ImageError{};
        char row[512];
        std::snprintf(row, sizeof row, "%s,%s,%d,%.6f,%llu,%.6g,%.6g,%.6g,%.4f,%.3f,%d,%d,%d\n",
                      std::string(accel::to_string(kind)).c_str(), iname.c_str(), spp, seconds,
                      (unsigned long long)stats.total(), err.rmse, err.rel_mse, err.mean,
                      seconds > 0 ? double(stats.total()) / seconds * 1e-6 : 0.0, build_ms, stats.threads,
                      set.width, set.height);
        csv += row;
        std::printf("%-10s %-8s %6d %10.4f %12llu %12.5g %12.5g\n", std::string(accel::to_string(kind)).c_str(),
                    iname.c_str(), spp, seconds, (unsigned long long)stats.total(), err.rmse, err.rel_mse);
        std::fflush(stdout);
        if (spp > o.max_spp / 2) break;  // also stops the doubling before it could overflow
    }
}

int run_converge(ConvergeCommand& o) {
    const auto limit = limit_threads(o.threads);
    Cluster* const cluster = Cluster::join(o.mpi);  // mpirun: every rank renders, rank 0 writes
    const bool writer = !cluster || cluster->root();
    const auto tiles = cluster ? cluster->frame_tiles() : nullptr;
    const std::vector<accel::AccelKind> kinds = parse_accels(o.accels);
    const std::vector<engine::IntegratorKind> integrators = parse_integrators(o.integrators);
    if (o.max_spp < 1) throw OptionError("--max-spp: must be at least 1");
    const engine::Image given_reference = read_reference(o);
    const std::filesystem::path dir(o.out_dir);
    std::error_code ec;
    if (writer) std::filesystem::create_directories(dir, ec);
    if (writer && (ec || !std::filesystem::is_directory(dir)))
        throw OptionError("--out: cannot create directory '" + o.out_dir + "'");

    const engine::Scene scene = load_scene(o.scene, writer);
    if (cluster)
        cluster->require_same(scene, settings_text(to_settings(o.render, integrators[0])) + ", accel " + o.accels +
                                         ", integrators " + o.integrators + ", max spp " + std::to_string(o.max_spp) +
                                         ", ref spp " + std::to_string(o.ref_spp) + ", repeat " +
                                         std::to_string(o.repeat) + ", reference " + std::to_string(!o.reference.empty()));
    const engine::LightSet lights(scene);
    ConvergeRun run{o, scene, lights, integrators, cluster, tiles.get(), writer, dir, o.build};
    run.build.layouts = accel::layouts_for(accel::TracePath::best);  // the renderer traces the SIMD paths only
    const int ref_spp = o.ref_spp > 0 ? o.ref_spp : 8 * o.max_spp;
    std::vector<engine::Image> references(integrators.size());
    std::string csv = "accel,integrator,spp,seconds,rays,rmse,rel_mse,mean,mrays_per_s,build_ms,threads,width,height\n";
    std::printf("%-10s %-8s %6s %10s %12s %12s %12s\n", "accel", "integr.", "spp", "seconds", "rays", "rmse", "rel_mse");
    for (std::size_t a = 0; a < kinds.size(); ++a) {
        accel::AccelPick pick = pick_structure(run, kinds[a], a == 0);
        const auto kind = pick.kind;
        const accel::Timer build_timer;
        const bool prebuilt = pick.built != nullptr;
        const auto structure = prebuilt ? std::move(pick.built) : accel::make_accel(kind, scene.mesh.view(), run.build);
        const double build_ms = prebuilt ? structure->stats().build_ms : build_timer.ms();
        for (std::size_t i = 0; i < integrators.size(); ++i) {
            const engine::RenderSettings set = to_settings(o.render, integrators[i]);
            const std::string iname(engine::to_string(integrators[i]));
            if (references[i].width == 0)
                references[i] = !o.reference.empty() ? given_reference
                                                     : render_reference(run, set, ref_spp, *structure, kind, iname);
            render_series(run, set, *structure, kind, build_ms, references[i], iname, csv);
        }
    }
    if (!writer) return 0;
    engine::write_file_atomic((dir / "converge.csv").string(), csv);
    std::printf("wrote %s%s\n", (dir / "converge.csv").string().c_str(), cluster ? cluster->on_ranks().c_str() : "");
    if (!o.no_plot) std::printf("%s\n", make_plot(dir, "arbor converge: " + scene.name).c_str());
    return 0;
}

}  // namespace

Run add_converge(CLI::App& cmd) {
    auto o = std::make_shared<ConvergeCommand>();
    o->render.width = 320;
    o->render.height = 240;
    add_scene_options(cmd, o->scene);
    cmd.add_option("--out", o->out_dir, "output folder for converge.csv, converge.png and the references")->required();
    cmd.add_option("--max-spp", o->max_spp, "largest samples per pixel (1, 2, 4, ... up to this)")
        ->check(CLI::Range(1, 1 << 16))->capture_default_str();
    cmd.add_option("--reference", o->reference, "reference OpenEXR image (default: rendered at --ref-spp)");
    cmd.add_option("--ref-spp", o->ref_spp, "samples per pixel of the rendered reference (default 8 x --max-spp)")
        ->check(CLI::Range(1, 1 << 20));
    cmd.add_option("--accel", o->accels, "structures to compare, comma-separated: " + accel::accel_kind_names())
        ->capture_default_str();
    add_build_options(cmd, o->build);
    cmd.add_option("--integrator", o->integrators, "integrators to compare, comma-separated: " + engine::integrator_names())
        ->check(parse_check("--integrator", [](const std::string& v) {
            for (const std::string& name : split_list(v)) parse_integrator_option(name);
            return 0;
        }))
        ->capture_default_str();
    cmd.add_option("--repeat", o->repeat, "render each point K times and keep the median time")
        ->check(CLI::Range(1, 100))->capture_default_str();
    add_render_options(cmd, o->render, true);
    cmd.add_flag("--no-plot", o->no_plot, "write the CSV only");
    cmd.add_flag("-v,--verbose", o->verbose, "print each plan and what it skipped");
    add_threads_option(cmd, o->threads);
    add_mpi_option(cmd, o->mpi);
    CLI::App* app = &cmd;
    return [o, app] {
        o->size_given = app->count("--width") > 0 || app->count("--height") > 0;
        return run_converge(*o);
    };
}

}  // namespace arbor::app
