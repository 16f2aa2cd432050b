#include "apps/arbor/bench_forward.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mpi/launcher.h"

namespace arbor::app {

namespace {

std::vector<std::string> bench_candidates() {
    std::vector<std::string> out;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) out.push_back((exe.parent_path() / "arbor-bench").string());
#ifdef ARBOR_BENCH_BUILD
    if (out.empty() || out.front() != ARBOR_BENCH_BUILD) out.push_back(ARBOR_BENCH_BUILD);
#endif
#ifdef ARBOR_BENCH_INSTALLED
    out.push_back(ARBOR_BENCH_INSTALLED);
#endif
    return out;
}

/// One line from the launcher's rank 0 only (under mpirun every rank gets here).
int fail(const std::string& what) {
    const mpi::Launch launch = mpi::detect_launch();
    if (!launch.launched || launch.rank == 0) std::fprintf(stderr, "arbor: bench: %s\n", what.c_str());
    // Exit 1, not 2: the command line is fine; a file arbor needs is missing, as when the MPI
    // module arbor_mpi.so is (spec/cli.md: 1 for an input file that cannot be used, 2 for options).
    return 1;
}

}  // namespace

int forward_bench(int argc, char** argv) {
    if (argc < 2 || std::strcmp(argv[1], "bench") != 0) return -1;
    std::vector<char*> args(argv, argv + argc);
    args.push_back(nullptr);
    static char name[] = "arbor";
    args[0] = name;
    std::string tried;
    for (const std::string& path : bench_candidates()) {
        if (::access(path.c_str(), X_OK) != 0) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        ::execv(path.c_str(), args.data());
        return fail("cannot run " + path + ": " + std::strerror(errno));
    }
    return fail("arbor-bench is not installed (looked for " + tried +
                "; it is built from perf/ with `cmake --build --preset release --target arbor-bench`)");
}

}  // namespace arbor::app
