#pragma once
/// WideCounts: what the counted single-ray walk of an N-wide layout did (WideBvhAccel::trace_counted),
/// summed over its rays: the work the model of docs/benchmarks.md ("Distance to the limit") prices
/// with the kernels' times and the bytes each node and block occupies.
#include <cstdint>

namespace arbor::accel {

struct WideCounts {
    std::uint64_t rays = 0;        ///< rays walked (traceable or not)
    std::uint64_t node_tests = 0;  ///< wide nodes whose N child boxes were tested (one SIMD slab test each)
    std::uint64_t blocks = 0;      ///< leaf blocks tested (one N-wide triangle test each)
    std::uint64_t triangles = 0;   ///< the triangles in those blocks (their used lanes)

    WideCounts& operator+=(const WideCounts& o) {
        rays += o.rays, node_tests += o.node_tests, blocks += o.blocks, triangles += o.triangles;
        return *this;
    }
};

}  // namespace arbor::accel
