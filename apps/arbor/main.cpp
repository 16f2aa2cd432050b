/// `arbor`: subcommand dispatch inside the single error boundary (apps/arbor/program.h).
#include "apps/arbor/bench_forward.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/program.h"
#include "apps/arbor/rank_guardian.h"
#include "accel/dispatch/kernel_set.h"
#include "simd/simd.h"

#include <cstring>

#ifndef ARBOR_VERSION
#define ARBOR_VERSION "unknown"
#endif

namespace {

/// `arbor --version` (spec/cli.md): the version and the SIMD kernel set in use: the one compiled
/// for the build's -march, or in a portable build the one chosen at run time (accel/dispatch/kernel_set.h).
std::string version_text() {
    const std::vector<std::string_view> sets = arbor::accel::kernel_sets_built();
    std::string text = std::string("arbor ") + ARBOR_VERSION + "\nSIMD kernels: " + std::string(arbor::accel::kernel_set());
    if (sets.size() == 1)
        return text + " (compiled for this build's -march: xsimd " + arbor::simd::FloatV::arch_type::name() + ", " +
               std::to_string(arbor::simd::FloatV::size) + " float lanes)";
    std::string names;
    for (const std::string_view s : sets) names += (names.empty() ? "" : ", ") + std::string(s);
    return text + " (portable build: chosen at run time from " + names + "; ARBOR_ISA=NAME forces one)";
}

/// The first argument that is not an option, when it names no subcommand: CLI11 would only say
/// that a subcommand is required.
std::string unknown_subcommand(int argc, char** argv, const CLI::App& app) {
    if (argc < 2 || argv[1][0] == '-') return {};
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
        if (sub->get_name() == argv[1]) return {};
        names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    return std::string("unknown subcommand '") + argv[1] + "' (expected one of " + names + ")";
}

}  // namespace

int main(int argc, char** argv) {
    // `arbor bench` becomes arbor-bench before anything else happens here, so that under mpirun
    // each rank is an arbor-bench with its own rank guardian (apps/arbor/bench_forward.h).
    if (const int status = arbor::app::forward_bench(argc, argv); status >= 0) return status;
    arbor::app::guard_rank();  // under a launcher: the rank goes on in a child, before any thread exists
    CLI::App app{"arbor: CPU ray tracing with comparable acceleration structures"};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "all subcommands' options");
    std::vector<std::pair<CLI::App*, arbor::app::Run>> commands;
    auto reg = [&](const char* name, const char* help, arbor::app::Run (*add)(CLI::App&)) {
        CLI::App* sub = app.add_subcommand(name, help);
        commands.emplace_back(sub, add(*sub));
    };
    reg("info", "load a model and describe it", arbor::app::add_info);
    reg("trace", "trace a .rays file and write a .hits file", arbor::app::add_trace);
    reg("rays", "generate primary, shadow, diffuse or random rays for a scene into a .rays file", arbor::app::add_rays);
    reg("stress", "the stiff-case suite: every structure and path against a double-precision oracle", arbor::app::add_stress);
    reg("render", "render a scene (the embedded default scene without SCENE)", arbor::app::add_render);
    reg("converge", "error against run time: renders at 1, 2, 4, ... spp against a reference", arbor::app::add_converge);
    reg("view", "the live viewer: serves a page at http://127.0.0.1:8080/ that renders SCENE as you move", arbor::app::add_view);
    // Listed for --help only: main() has forwarded `arbor bench ...` to arbor-bench before parsing.
    app.add_subcommand("bench",
                       "the benchmark matrix: every structure, scene, ray kind and path, validated then timed, beside "
                       "Embree; runs `arbor-bench bench` with the same arguments (perf/README.md)")
        ->prefix_command();
    for (int i = 0; i < argc; ++i) arbor::app::command_line() += (i ? " " : "") + std::string(i ? argv[i] : "arbor");
    std::string version;
    try {
        version = version_text();  // chooses the kernel set: a bad ARBOR_ISA stops here
    } catch (const std::exception& e) {
        return arbor::app::failure(2, e.what());
    }
    app.set_version_flag("--version", version, "print the version and the SIMD kernel set, then exit");
    if (const std::string unknown = unknown_subcommand(argc, argv, app); !unknown.empty()) {
        return arbor::app::failure(2, unknown);
    }
    return arbor::app::run_guarded(app, [&] {
        app.parse(argc, argv);
        for (auto& [sub, run] : commands)
            if (sub->parsed()) return run();
        return 2;
    });
}
