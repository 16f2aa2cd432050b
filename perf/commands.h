#pragma once
/// The sub-commands of `arbor-bench` (perf/main.cpp), the lab's one benchmark tool. Each but
/// `bench` takes the sub-command's own arguments (argv[0] is "arbor-bench NAME") and returns the
/// exit status; `bench` registers its options on a CLI11 app and returns the function that runs it,
/// inside the error boundary `arbor` uses (apps/arbor/program.h).
#include <CLI/CLI.hpp>
#include <functional>

namespace arbor::perf {

/// `bench`: the benchmark matrix, also under mpirun (= `arbor bench`; perf/cmd_bench.cpp).
std::function<int()> add_bench_command(CLI::App& cmd);
/// `paths`: arbor's traversal paths and BVH widths against Embree on the same .rays files.
int paths_command(int argc, char** argv);
/// `bvh`: build time, SAH cost and scalar trace speed of the BVH builders.
int bvh_command(int argc, char** argv);
/// `lbvh`: the LBVH build variants against bvh-sah, bvh-median and Embree.
int lbvh_command(int argc, char** argv);
/// `kdtree`: build time, SAH cost, memory and scalar trace speed of the kd-tree.
int kdtree_command(int argc, char** argv);
/// `load`: loading speed per mesh format, in seconds per million triangles.
int load_command(int argc, char** argv);
/// `build-once`: one build in a fresh process (Embree or an arbor structure).
int build_once_command(int argc, char** argv);
/// `trace-once`: one ray file traced once on one thread, for callgrind.
int trace_once_command(int argc, char** argv);
/// `instances`: a mesh placed as instances against the same scene flattened (perf/instances_bench.cpp).
int instances_command(int argc, char** argv);
/// `limit`: the kernels' times with hot caches, the bandwidth, and the counted walk's node and
/// block tests per ray (perf/limit_bench.cpp; scripts/limit_model.py makes the table).
int limit_command(int argc, char** argv);
/// `kernels`: Google Benchmark microbenchmarks of the simd/ kernels (when libbenchmark-dev was
/// found; ARBOR_HAVE_GBENCH).
int kernels_command(int argc, char** argv);

}  // namespace arbor::perf
