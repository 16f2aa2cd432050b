#include "accel/bvh/binary_bvh.h"

#include <algorithm>

namespace arbor::accel {

BvhTreeStats bvh_tree_stats(const BinaryBvh& bvh, float traversal_cost, float intersection_cost) {
    BvhTreeStats s;
    if (bvh.nodes.empty()) return s;
    const double root_area = bvh.nodes[0].box.area();
    double cost = 0.0, depth_sum = 0.0;
    // Children come after their parents: one forward pass hands every node its depth.
    std::vector<std::uint32_t> depth(bvh.nodes.size(), 0);
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhBuildNode& n = bvh.nodes[i];
        ++s.nodes;
        if (n.is_leaf()) {
            ++s.leaves;
            s.max_depth = std::max(s.max_depth, depth[i]);
            s.max_leaf_size = std::max(s.max_leaf_size, n.count);
            depth_sum += depth[i];
            cost += n.box.area() * n.count * intersection_cost;
        } else {
            cost += n.box.area() * traversal_cost;
            depth[n.first] = depth[n.first + 1] = depth[i] + 1;
        }
    }
    s.mean_leaf_depth = s.leaves ? depth_sum / double(s.leaves) : 0.0;
    s.sah_cost = root_area > 0.0 ? cost / root_area : 0.0;
    return s;
}

std::string validate_bvh(const BinaryBvh& bvh, const TriangleView& tris, std::uint32_t max_leaf_size) {
    const std::size_t n = tris.triangle_count();
    std::vector<std::uint8_t> seen(n, 0);
    if (bvh.nodes.empty()) {
        for (std::size_t t = 0; t < n; ++t)
            if (tris.triangle_is_finite(t)) return "empty tree but triangle " + std::to_string(t) + " is finite";
        return {};
    }
    std::vector<std::uint8_t> visited(bvh.nodes.size(), 0);
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        if (i >= bvh.nodes.size()) return "node index " + std::to_string(i) + " out of range";
        if (visited[i]++) return "node " + std::to_string(i) + " reached twice";
        const BvhBuildNode& node = bvh.nodes[i];
        if (node.is_leaf()) {
            if (max_leaf_size && node.count > max_leaf_size)
                return "leaf " + std::to_string(i) + " holds " + std::to_string(node.count) + " > " + std::to_string(max_leaf_size);
            if (std::size_t(node.first) + node.count > bvh.prim_ids.size()) return "leaf " + std::to_string(i) + " range out of prim_ids";
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                const std::uint32_t t = bvh.prim_ids[k];
                if (t >= n) return "prim id " + std::to_string(t) + " out of range";
                if (!tris.triangle_is_finite(t)) return "non-finite triangle " + std::to_string(t) + " referenced";
                if (seen[t]++) return "triangle " + std::to_string(t) + " referenced twice";
                if (!node.box.contains(tris.triangle_bounds(t)))
                    return "leaf " + std::to_string(i) + " box does not contain triangle " + std::to_string(t);
            }
        } else {
            if (std::size_t(node.first) + 1 >= bvh.nodes.size()) return "node " + std::to_string(i) + " children out of range";
            if (node.first <= i) return "node " + std::to_string(i) + " has a child index not after it";
            for (std::uint32_t c : {node.first, node.first + 1}) {
                if (!node.box.contains(bvh.nodes[c].box))
                    return "node " + std::to_string(i) + " box does not contain child " + std::to_string(c);
                stack.push_back(c);
            }
        }
    }
    for (std::size_t t = 0; t < n; ++t)
        if (tris.triangle_is_finite(t) && !seen[t]) return "finite triangle " + std::to_string(t) + " not referenced";
    return {};
}

}  // namespace arbor::accel
