/// `arbor`: subcommand dispatch and the single error boundary. Bad input (InputError, option
/// errors) prints one line on stderr and exits 1 or 2; nothing is caught anywhere else. Under
/// mpirun the line comes from rank 0 only, naming the rank that failed, and the whole job stops
/// (apps/arbor/cluster.h).
#include "apps/arbor/cluster.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "apps/arbor/rank_guardian.h"
#include "accel/dispatch/kernel_set.h"
#include "accel/factory/memory_estimate.h"
#include "engine/error.h"
#include "mpi/launcher.h"
#include "simd/simd.h"

#include <cstdio>
#include <cstring>
#include <new>

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

/// Prints "arbor: <what>" and returns `code`; in an MPI job, stops the whole job instead (rank 0
/// prints the line with the failing rank). Before a job is joined (option errors), only the
/// launcher's rank 0 prints, so that N ranks do not print N copies.
int failure(int code, const std::string& what) {
    if (arbor::app::Cluster* c = arbor::app::Cluster::current()) c->fail(code, what);
    const arbor::mpi::Launch launch = arbor::mpi::detect_launch();
    if (!launch.launched || launch.rank == 0) std::fprintf(stderr, "arbor: %s\n", what.c_str());
    return code;
}

}  // namespace

int main(int argc, char** argv) {
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
#ifdef ARBOR_HAVE_BENCH
    reg("bench", "the benchmark matrix: every structure, scene, ray kind and path, validated then timed (perf/README.md)",
        arbor::app::add_bench);
#endif
    for (int i = 0; i < argc; ++i) arbor::app::command_line() += (i ? " " : "") + std::string(i ? argv[i] : "arbor");
    std::string version;
    try {
        version = version_text();  // chooses the kernel set: a bad ARBOR_ISA stops here
    } catch (const std::exception& e) {
        return failure(2, e.what());
    }
    app.set_version_flag("--version", version, "print the version and the SIMD kernel set, then exit");
    if (const std::string unknown = unknown_subcommand(argc, argv, app); !unknown.empty()) {
        return failure(2, unknown);
    }
    try {
        app.parse(argc, argv);
        for (auto& [sub, run] : commands)
            if (sub->parsed()) {
                const int status = run();
                arbor::app::Cluster* cluster = arbor::app::Cluster::current();
                if (status != 0 && cluster) cluster->fail(status, "stopped with exit status " + std::to_string(status));
                arbor::app::Cluster::leave();
                return status;
            }
        return 2;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return failure(2, e.what());
    } catch (const arbor::accel::MemoryLimitError& e) {
        return failure(1, std::string("--max-memory: ") + e.what());
    } catch (const arbor::app::OptionError& e) {
        return failure(2, e.what());
    } catch (const arbor::engine::InputError& e) {
        return failure(1, e.what());
    } catch (const std::bad_alloc&) {
        return failure(3, "out of memory");
    } catch (const std::exception& e) {
        return failure(4, e.what());
    }
}
