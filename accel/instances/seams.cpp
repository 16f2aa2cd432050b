#include "accel/instances/seams.h"

#include <algorithm>
#include <bit>
#include <unordered_map>
#include <utility>

namespace arbor::accel {

namespace {

struct Corner {
    std::uint32_t x, y, z;  ///< the bits of the coordinates: equal positions, equal keys
    bool operator==(const Corner&) const = default;
};
struct CornerHash {
    std::size_t operator()(const Corner& c) const {
        std::uint64_t h = c.x * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) + c.y * 0xBF58476D1CE4E5B9ull;
        h ^= (h >> 31) + c.z * 0x94D049BB133111EBull;
        return std::size_t(h ^ (h >> 32));
    }
};
struct EdgeHash {
    std::size_t operator()(const std::pair<std::uint32_t, std::uint32_t>& e) const {
        return std::size_t((std::uint64_t(e.first) << 32 | e.second) * 0x9E3779B97F4A7C15ull >> 7);
    }
};

}  // namespace

SeamSet find_seams(const TriangleView& mesh) {
    const std::size_t n = mesh.triangle_count();
    SeamSet out;
    out.flag.assign(n, 0);
    // One id per distinct position (+0 and -0 are one position).
    std::unordered_map<Corner, std::uint32_t, CornerHash> ids;
    std::vector<std::uint32_t> id(mesh.vertex_count());
    const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0.0f ? 0.0f : f); };
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        id[v] = ids.try_emplace(Corner{bits(mesh.x[v]), bits(mesh.y[v]), bits(mesh.z[v])}, std::uint32_t(ids.size()))
                    .first->second;
    std::unordered_map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t, EdgeHash> uses;
    const auto corners = [&](std::size_t t, std::uint32_t c[3]) {
        for (int k = 0; k < 3; ++k) c[k] = id[mesh.indices[3 * t + std::size_t(k)]];
        return mesh.triangle_is_finite(t) && c[0] != c[1] && c[1] != c[2] && c[0] != c[2];
    };
    for (std::size_t t = 0; t < n; ++t) {
        std::uint32_t c[3];
        if (!corners(t, c)) continue;
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(c[k], c[(k + 1) % 3])];
    }
    std::vector<std::uint8_t> boundary(ids.size(), 0);
    for (const auto& [edge, count] : uses)
        if (count == 1) boundary[edge.first] = boundary[edge.second] = 1;
    for (std::size_t t = 0; t < n; ++t) {
        std::uint32_t c[3];
        if (!corners(t, c)) continue;
        if (boundary[c[0]] || boundary[c[1]] || boundary[c[2]]) {
            out.flag[t] = 1;
            out.tris.push_back(std::uint32_t(t));
        }
    }
    return out;
}

}  // namespace arbor::accel
