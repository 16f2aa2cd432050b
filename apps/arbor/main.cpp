/// `arbor`: subcommand dispatch and the single error boundary. Bad input (InputError, option
/// errors) prints one line on stderr and exits 1 or 2; nothing is caught anywhere else.
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "accel/core/memory_estimate.h"
#include "engine/error.h"
#include "simd/simd.h"

#include <cstdio>
#include <cstring>
#include <new>

#ifndef ARBOR_VERSION
#define ARBOR_VERSION "unknown"
#endif

namespace {

/// `arbor --version` (spec/cli.md): the version and the SIMD kernel set compiled in, which is the
/// one in use (the kernels are instantiated for the build's -march; there is no run-time dispatch).
std::string version_text() {
    return std::string("arbor ") + ARBOR_VERSION + "\nSIMD kernels: " + arbor::simd::FloatV::arch_type::name() + " (" +
           std::to_string(arbor::simd::FloatV::size) + " float lanes, compiled for this build's -march)";
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
    app.set_version_flag("--version", version_text(), "print the version and the SIMD kernel set, then exit");
    if (const std::string unknown = unknown_subcommand(argc, argv, app); !unknown.empty()) {
        std::fprintf(stderr, "arbor: %s\n", unknown.c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
        for (auto& [sub, run] : commands)
            if (sub->parsed()) return run();
        return 2;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "arbor: %s\n", e.what());
        return 2;
    } catch (const arbor::accel::MemoryLimitError& e) {
        std::fprintf(stderr, "arbor: --max-memory: %s\n", e.what());
        return 1;
    } catch (const arbor::app::OptionError& e) {
        std::fprintf(stderr, "arbor: %s\n", e.what());
        return 2;
    } catch (const arbor::engine::InputError& e) {
        std::fprintf(stderr, "arbor: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "arbor: out of memory\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor: %s\n", e.what());
        return 4;
    }
}
