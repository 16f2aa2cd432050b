#pragma once
/// The top level of a two-level scene: a binary BVH over the instances' world boxes (one item per
/// instance, up to 2 per leaf), built by object median on the longest axis of the centroids.
/// Small (one node per instance or so) and walked once per ray or point, in double precision, so
/// that its boxes never lose a ray or a point that the bottom structures would answer.
#include "accel/core/geometry.h"

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace arbor::accel {

class TopBvh {
public:
    /// Builds over `boxes` (item i = boxes[i]); items with an empty box are left out.
    static TopBvh build(std::span<const Bounds> boxes);

    /// Calls f(item, t_enter) for every item whose box the segment o + t d, t in [tnear, tfar],
    /// meets, t_enter being where the segment enters the box (ray o, d with tnear <= tfar; a zero
    /// component of d meets a slab only from inside it).
    template <class F>
    void ray_items(const double o[3], const double d[3], double tnear, double tfar, F&& f) const;

    /// Calls f(item, box_distance2) for items nearest box first; stops at boxes farther than
    /// sqrt(reach2), which f may lower as it finds closer answers.
    template <class F>
    void nearest_items(const double p[3], double& reach2, F&& f) const;

    std::size_t memory_bytes() const { return nodes_.size() * sizeof(Node) + items_.size() * sizeof(std::uint32_t); }
    bool empty() const { return nodes_.empty(); }

private:
    struct Node {
        Bounds box;
        std::uint32_t first = 0, count = 0;  ///< a leaf: items_[first, first + count)
        std::uint32_t right = 0;             ///< an interior node: children at this + 1 and `right`
    };
    static double dist2(const Bounds& b, const double p[3]) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double lo = b.lo[k], hi = b.hi[k];
            const double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0.0);
            s += e * e;
        }
        return s;
    }
    std::uint32_t build_node(std::span<const Bounds> boxes, std::uint32_t first, std::uint32_t count);

    std::vector<Node> nodes_;
    std::vector<std::uint32_t> items_;
};

template <class F>
void TopBvh::ray_items(const double o[3], const double d[3], double tnear, double tfar, F&& f) const {
    if (nodes_.empty()) return;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    // 1/d in double: its rounding (~1e-16) is far inside the boxes' outward rounding to float.
    const double inv[3] = {d[0] != 0.0 ? 1.0 / d[0] : 0.0, d[1] != 0.0 ? 1.0 / d[1] : 0.0, d[2] != 0.0 ? 1.0 / d[2] : 0.0};
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        double t0 = tnear, t1 = tfar;
        for (int k = 0; k < 3 && t0 <= t1; ++k) {
            const double lo = n.box.lo[k], hi = n.box.hi[k];
            if (d[k] == 0.0) {
                if (o[k] < lo || o[k] > hi) t0 = 1.0, t1 = 0.0;
                continue;
            }
            double a = (lo - o[k]) * inv[k], b = (hi - o[k]) * inv[k];
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a), t1 = std::min(t1, b);
        }
        if (!(t0 <= t1)) continue;
        if (n.count > 0) {
            for (std::uint32_t i = 0; i < n.count; ++i) f(items_[n.first + i], t0);
        } else {
            stack[top++] = n.right;
            stack[top++] = std::uint32_t(&n - nodes_.data()) + 1;
        }
    }
}

template <class F>
void TopBvh::nearest_items(const double p[3], double& reach2, F&& f) const {
    if (nodes_.empty()) return;
    struct Entry {
        std::uint32_t node;
        double d2;
    };
    Entry stack[64];
    int top = 0;
    stack[top++] = {0, dist2(nodes_[0].box, p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > reach2) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
            for (std::uint32_t i = 0; i < n.count; ++i) {
                const std::uint32_t item = items_[n.first + i];
                f(item);
            }
            continue;
        }
        // The nearer child is walked first (pushed last).
        const std::uint32_t a = e.node + 1, b = n.right;
        const double da = dist2(nodes_[a].box, p), db = dist2(nodes_[b].box, p);
        if (da <= db) {
            stack[top++] = {b, db};
            stack[top++] = {a, da};
        } else {
            stack[top++] = {a, da};
            stack[top++] = {b, db};
        }
    }
}

}  // namespace arbor::accel
