#pragma once
/// The machine side of the limit model (`arbor-bench limit kernels`, docs/benchmarks.md "Distance
/// to the limit"): the time of one wide node test and one triangle block test with hot caches (a
/// working set in L1, looped, results kept), and the streaming read bandwidth of memory.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace arbor::perf {

/// The kernels of width `width`: best (least) and median of 101 short timings, in ns per test; cycles are
/// TSC (reference) cycles, ns x the TSC's rate: the VM has no core cycle counter.
struct KernelTimes {
    std::size_t width = 0;
    double node_ns = 0, node_ns_median = 0, node_cycles = 0;     ///< ray_boxes_plain, independent tests
    double block_ns = 0, block_ns_median = 0, block_cycles = 0;  ///< ray_triangles<T, true>, independent tests
    double node_chain_ns = 0, node_chain_ns_median = 0, node_chain_cycles = 0;  ///< node tests each chosen by the last
    std::uint64_t checked_tests = 0;  ///< lanes checked against slab_test and woop_test (all equal, else it throws)
    double box_hit_fraction = 0;      ///< of the boxes tested
    double block_hit_fraction = 0;    ///< of the blocks tested, those with a hit (no early out)
};

/// GB/s (1e9 bytes) of a streaming read by 1 and 2 threads: of a buffer far larger than the caches
/// (memory, best of 15) and of one that stays in the last-level cache (cache, read 16 times per
/// timing, best of 51).
struct Bandwidth {
    std::size_t buffer_mib = 0, cache_mib = 0;
    double gbs_1 = 0, gbs_2 = 0;
    double cache_gbs_1 = 0, cache_gbs_2 = 0;
};

/// The TSC's rate in GHz, against the steady clock over 0.1 s.
double tsc_ghz();
/// The kernels at every width this build has (16 with AVX-512, 8 with AVX2, 4). Throws
/// std::runtime_error when a kernel's answer differs from the scalar oracle's.
std::vector<KernelTimes> time_wide_kernels(double tsc_ghz);
/// The streaming read of a buffer of `mib` MiB (far larger than the caches) and of one of
/// `cache_mib` MiB (read once before the timing, so that it is in the caches).
Bandwidth measure_bandwidth(std::size_t mib, std::size_t cache_mib);

}  // namespace arbor::perf
