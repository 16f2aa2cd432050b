#include "accel/core/closed_mesh.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <vector>

namespace arbor::accel {

bool is_closed_mesh(std::span<const std::uint32_t> indices) {
    const std::size_t tris = indices.size() / 3;
    // Each edge as one 64-bit key, the smaller vertex number high; sorted, every key must come in
    // a run of exactly two. (Any order of equal keys is the same key, so the unstable sort's
    // scheduling cannot change the answer.)
    std::vector<std::uint64_t> edges(3 * tris);
    for (std::size_t t = 0; t < tris; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = indices[3 * t + k], b = indices[3 * t + (k + 1) % 3];
            edges[3 * t + k] = std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
        }
    tbb::parallel_sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size(); i += 2)
        if (i + 1 >= edges.size() || edges[i] != edges[i + 1] || (i + 2 < edges.size() && edges[i + 2] == edges[i]))
            return false;
    return true;
}

}  // namespace arbor::accel
