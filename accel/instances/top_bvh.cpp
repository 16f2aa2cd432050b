#include "accel/instances/top_bvh.h"

#include <algorithm>

namespace arbor::accel {

TopBvh TopBvh::build(std::span<const Bounds> boxes) {
    TopBvh t;
    for (std::size_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].empty()) t.items_.push_back(std::uint32_t(i));
    if (t.items_.empty()) return t;
    t.nodes_.reserve(2 * t.items_.size());
    t.build_node(boxes, 0, std::uint32_t(t.items_.size()));
    return t;
}

std::uint32_t TopBvh::build_node(std::span<const Bounds> boxes, std::uint32_t first, std::uint32_t count) {
    const auto index = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    Bounds box, centers;
    for (std::uint32_t i = first; i < first + count; ++i) {
        box.grow(boxes[items_[i]]);
        centers.grow(boxes[items_[i]].center());
    }
    nodes_[index].box = box;
    if (count <= 2) {
        nodes_[index].first = first, nodes_[index].count = count;
        return index;
    }
    const Vec3f e = centers.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const std::uint32_t half = count / 2;
    // Ties on the centre broken by item number: the tree does not depend on the sort's order.
    std::nth_element(items_.begin() + first, items_.begin() + first + half, items_.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) {
                         const float ca = boxes[a].center()[axis], cb = boxes[b].center()[axis];
                         return ca < cb || (ca == cb && a < b);
                     });
    build_node(boxes, first, half);
    const std::uint32_t right = build_node(boxes, first + half, count - half);
    nodes_[index].right = right;
    return index;
}

}  // namespace arbor::accel
