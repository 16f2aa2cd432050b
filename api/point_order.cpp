#include "api/point_order.h"

#include "accel/lbvh/morton.h"

#include <tbb/parallel_sort.h>

#include <cmath>
#include <limits>

namespace arbor {

namespace {

/// Below this many points the given order is kept: the sort would cost more than it saves.
constexpr std::size_t min_sorted = 64;

bool finite(const accel::Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::vector<std::uint32_t> spatial_order(const PointArrays& p, CallArena& arena) {
    if (p.count < min_sorted || p.count > std::numeric_limits<std::uint32_t>::max()) return {};
    accel::Vec3f lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    for (std::size_t i = 0; i < p.count; ++i) {
        const accel::Vec3f v = read_vec3(p.xyz, p.stride, i);
        if (!finite(v)) continue;
        lo = simd::vmin(lo, v), hi = simd::vmax(hi, v);
    }
    // 10 bits per axis over the box (in double: the box of huge coordinates has no float extent).
    double scale[3], base[3];
    for (int k = 0; k < 3; ++k) {
        const double ext = double(hi[k]) - double(lo[k]);
        base[k] = lo[k];
        scale[k] = ext > 0.0 ? 1023.0 / ext : 0.0;
    }
    std::vector<std::uint64_t> keys(p.count);
    for (std::size_t i = 0; i < p.count; ++i) {
        const accel::Vec3f v = read_vec3(p.xyz, p.stride, i);
        std::uint64_t code = std::uint64_t(1) << 30;  // after every finite point's code
        if (finite(v)) {
            std::uint32_t q[3];
            for (int k = 0; k < 3; ++k) q[k] = std::uint32_t(std::min(1023.0, std::max(0.0, (double(v[k]) - base[k]) * scale[k])));
            code = accel::morton_encode30(q[0], q[1], q[2]);
        }
        keys[i] = code << 32 | std::uint64_t(i);  // unique keys: the order is fixed
    }
    arena.execute([&] { tbb::parallel_sort(keys.begin(), keys.end()); });
    std::vector<std::uint32_t> order(p.count);
    for (std::size_t i = 0; i < p.count; ++i) order[i] = std::uint32_t(keys[i]);
    return order;
}

}  // namespace arbor
