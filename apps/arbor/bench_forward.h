#pragma once
/// `arbor bench ARGS` is `arbor-bench bench ARGS`: the benchmark matrix, with Embree beside arbor,
/// lives in the lab tool arbor-bench (perf/), so that `arbor` links neither Embree nor the
/// benchmark harness.
namespace arbor::app {

/// When argv[1] is "bench", replaces this process with arbor-bench (execv), found beside this
/// executable, then at its build-tree path, then in the install's bindir; it is run as
/// `arbor bench ARGS` (argv[0] "arbor"), so its messages and reports read as they always did.
/// Returns -1 when argv[1] is not "bench"; otherwise returns only when arbor-bench cannot be run,
/// after one line on stderr, with the exit status.
int forward_bench(int argc, char** argv);

}  // namespace arbor::app
