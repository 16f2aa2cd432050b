#include "accel/instances/top_bvh.h"

#include <algorithm>
#include <stdexcept>

namespace arbor::accel {

namespace {
/// Moves the median of items [first, first + count) on the longest axis of their boxes' centres
/// to first + count / 2, the smaller ones before it. Ties on the centre broken by item number: the
/// trees do not depend on the sort's order.
void split_median(std::span<const Bounds> boxes, std::vector<std::uint32_t>& items, std::uint32_t first,
                  std::uint32_t count) {
    Bounds centers;
    for (std::uint32_t i = first; i < first + count; ++i) centers.grow(boxes[items[i]].center());
    const Vec3f e = centers.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    std::nth_element(items.begin() + first, items.begin() + first + count / 2, items.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) {
                         const float ca = boxes[a].center()[axis], cb = boxes[b].center()[axis];
                         return ca < cb || (ca == cb && a < b);
                     });
}
}  // namespace

TopBvh TopBvh::build(std::span<const Bounds> boxes) {
    TopBvh t;
    if (boxes.size() >= item_bit) throw std::length_error("instances: 2^31 or more placements");
    for (std::size_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].empty()) t.items_.push_back(std::uint32_t(i));
    if (t.items_.empty()) return t;
    std::vector<std::uint32_t> items = t.items_;
    t.nodes_.reserve(2 * t.items_.size());
    t.build_node(boxes, 0, std::uint32_t(t.items_.size()));
    t.wide_.reserve(t.items_.size() / 2 + 1);
    t.build_wide(boxes, items, 0, std::uint32_t(items.size()));
    return t;
}

std::uint32_t TopBvh::build_node(std::span<const Bounds> boxes, std::uint32_t first, std::uint32_t count) {
    const auto index = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    Bounds box;
    for (std::uint32_t i = first; i < first + count; ++i) box.grow(boxes[items_[i]]);
    nodes_[index].box = box;
    if (count <= 2) {
        nodes_[index].first = first, nodes_[index].count = count;
        return index;
    }
    const std::uint32_t half = count / 2;
    split_median(boxes, items_, first, count);
    build_node(boxes, first, half);
    const std::uint32_t right = build_node(boxes, first + half, count - half);
    nodes_[index].right = right;
    return index;
}

std::uint32_t TopBvh::build_wide(std::span<const Bounds> boxes, std::vector<std::uint32_t>& items, std::uint32_t first,
                                 std::uint32_t count) {
    const auto index = std::uint32_t(wide_.size());
    wide_.emplace_back();
    // Up to `width` parts: the items themselves, or the halves of the median split, halved again
    // until there are `width` parts.
    std::uint32_t part_first[width], part_count[width], parts = 0;
    if (count <= width) {
        for (std::uint32_t i = 0; i < count; ++i) part_first[parts] = first + i, part_count[parts++] = 1;
    } else {
        part_first[0] = first, part_count[0] = count, parts = 1;
        while (parts < width) {
            for (std::uint32_t p = parts; p-- > 0;) {
                const std::uint32_t f = part_first[p], c = part_count[p];
                split_median(boxes, items, f, c);
                part_first[2 * p] = f, part_count[2 * p] = c / 2;
                part_first[2 * p + 1] = f + c / 2, part_count[2 * p + 1] = c - c / 2;
            }
            parts *= 2;
        }
    }
    for (std::uint32_t s = 0; s < width; ++s) {
        if (s >= parts) {
            wide_[index].box.set_empty(s);
            continue;
        }
        Bounds box;
        for (std::uint32_t i = part_first[s]; i < part_first[s] + part_count[s]; ++i) box.grow(boxes[items[i]]);
        const std::uint32_t child = part_count[s] == 1 ? (items[part_first[s]] | item_bit)
                                                       : build_wide(boxes, items, part_first[s], part_count[s]);
        // (wide_ may have grown: index, not a reference.)
        wide_[index].box.set(s, box.lo, box.hi);
        wide_[index].child[s] = child;
    }
    return index;
}

}  // namespace arbor::accel
