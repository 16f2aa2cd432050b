/// `arbor_bench`: the benchmark matrix (perf/README.md). Validates every configuration first,
/// then times it, and writes bench.json, bench.csv and bench.md into --out. The same command is
/// `arbor bench`, which also runs under mpirun (spec/cli.md, "Across machines").
#include "engine/error.h"
#include "mpi/launcher.h"
#include "perf/bench_cli.h"

#include <cstdio>
#include <new>

int main(int argc, char** argv) {
    CLI::App app{"arbor_bench: every structure on every scene and ray kind, validated then timed, beside Embree"};
    const auto command = arbor::perf::add_bench_options(app);
    try {
        app.parse(argc, argv);
        if (arbor::mpi::detect_launch().launched)
            throw arbor::engine::InputError(
                "arbor_bench runs alone; under mpirun, run `arbor bench` (the same options), which spreads the "
                "scenes over the ranks");
        arbor::perf::BenchRunContext ctx;
        for (int i = 0; i < argc; ++i) ctx.command += (i ? " " : "") + std::string(i ? argv[i] : "arbor_bench");
        return arbor::perf::run_bench_command(*command, ctx);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 2;
    } catch (const arbor::engine::InputError& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "arbor_bench: out of memory\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 4;
    }
}
