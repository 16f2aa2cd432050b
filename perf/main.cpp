/// `arbor-bench SUB-COMMAND ARGS`: the lab's benchmark tool (perf/README.md), one executable with
/// a sub-command per benchmark. `bench` is the benchmark matrix that `arbor bench` forwards to
/// (apps/arbor/bench_forward.h); it runs under mpirun as `arbor` does, with the same rank guardian,
/// MPI job and error boundary (the library arbor_program). Run as `arbor bench` (argv[0] "arbor"),
/// its messages and reports name `arbor bench`, as they did before the tool was split out.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "apps/arbor/program.h"
#include "apps/arbor/rank_guardian.h"
#include "perf/commands.h"

namespace {

struct SubCommand {
    const char* name;
    const char* help;
    int (*run)(int argc, char** argv);
};

int bench_main(int argc, char** argv);
#ifndef ARBOR_HAVE_GBENCH
int kernels_not_built(int, char**) {
    std::fprintf(stderr,
                 "arbor-bench: kernels: not built (Google Benchmark was not found when arbor was configured; "
                 "install libbenchmark-dev and reconfigure)\n");
    return 1;
}
#endif

const std::vector<SubCommand>& sub_commands() {
    using namespace arbor::perf;
    static const std::vector<SubCommand> subs = {
        {"bench",
         "the benchmark matrix: every structure, scene, ray kind and path, validated then timed, beside "
         "Embree (= arbor bench; also under mpirun)",
         bench_main},
        {"paths", "arbor's traversal paths and BVH widths against Embree's calls on the same .rays files",
         paths_command},
        {"bvh", "build time, SAH cost and scalar trace speed of the BVH builders, beside Embree's build", bvh_command},
        {"lbvh", "the LBVH build variants and their step times against bvh-sah, bvh-median and Embree", lbvh_command},
        {"kdtree", "build time, SAH cost, memory and scalar trace speed of the kd-tree, beside Embree's build",
         kdtree_command},
        {"instances", "a mesh placed as instances against the same scene flattened: build, trace, memory",
         instances_command},
        {"load", "loading speed per mesh format (OBJ, PLY, GLB), in seconds per million triangles", load_command},
        {"build-once", "one build in a fresh process (Embree or an arbor structure), as a user meets it",
         build_once_command},
        {"trace-once", "one ray file traced once on one thread by an arbor path or an Embree call, for callgrind",
         trace_once_command},
        {"limit", "the limit model's inputs: kernel times with hot caches, bandwidth, node and block tests per ray",
         limit_command},
#ifdef ARBOR_HAVE_GBENCH
        {"kernels", "Google Benchmark microbenchmarks of the SIMD box and triangle kernels", kernels_command},
#else
        {"kernels", "Google Benchmark microbenchmarks of the SIMD kernels (not built: libbenchmark-dev missing)",
         kernels_not_built},
#endif
    };
    return subs;
}

/// `bench`: the matrix inside the error boundary `arbor` uses, as a rank under mpirun.
int bench_main(int argc, char** argv) {
    arbor::app::guard_rank();  // under a launcher: the rank goes on in a child, before any thread exists
    CLI::App app{
        "the benchmark matrix: every structure on every scene and ray kind, validated then timed, beside "
        "Embree"};
    app.name(arbor::app::program_name() + " bench");
    const auto run = arbor::perf::add_bench_command(app);
    for (int i = 0; i < argc; ++i)
        arbor::app::command_line() += (i ? " " : "") + std::string(i ? argv[i] : app.get_name());
    return arbor::app::run_guarded(app, [&] {
        app.parse(argc, argv);
        return run();
    });
}

void usage(std::FILE* out) {
    std::fprintf(out,
                 "arbor-bench: the benchmarks of arbor (perf/README.md)\nUsage: arbor-bench SUB-COMMAND [ARGS]\n"
                 "       arbor-bench SUB-COMMAND --help\n\nSub-commands:\n");
    for (const SubCommand& s : sub_commands()) std::fprintf(out, "  %-11s %s\n", s.name, s.help);
}

}  // namespace

int main(int argc, char** argv) {
    // `arbor bench` runs this as "arbor bench ARGS" (apps/arbor/bench_forward.cpp).
    const bool as_arbor = argc > 0 && std::strcmp(argv[0], "arbor") == 0;
    arbor::app::program_name() = as_arbor ? "arbor" : "arbor-bench";
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    std::string names;
    for (const SubCommand& s : sub_commands()) {
        if (std::strcmp(argv[1], s.name) == 0) {
            // The sub-command sees its own arguments, with "arbor-bench NAME" as its program name.
            std::string program = arbor::app::program_name() + " " + s.name;
            std::vector<char*> args(argv + 1, argv + argc);
            args[0] = program.data();
            args.push_back(nullptr);
            return s.run(argc - 1, args.data());
        }
        names += (names.empty() ? "" : ", ") + std::string(s.name);
    }
    std::fprintf(stderr, "arbor-bench: unknown sub-command '%s' (expected one of %s)\n", argv[1], names.c_str());
    return 2;
}
