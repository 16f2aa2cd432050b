#include "engine/formats/tristrip.h"

namespace arbor::engine::formats {

StripCounts strip_triangles(std::span<const std::int64_t> indices, std::vector<std::array<std::int64_t, 3>>& out) {
    StripCounts counts;
    std::size_t start = 0;  // first index of the current strip
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] == -1) {
            start = i + 1;
            continue;
        }
        if (i < start + 2) continue;
        const std::int64_t a = indices[i - 2], b = indices[i - 1], c = indices[i];
        if (a == b || b == c || a == c) {
            ++counts.degenerate;
            continue;
        }
        // Window k = i - start - 2: odd windows are flipped to keep the strip's orientation.
        if ((i - start) % 2 == 0)
            out.push_back({a, b, c});
        else
            out.push_back({b, a, c});
        ++counts.triangles;
    }
    return counts;
}

}  // namespace arbor::engine::formats
