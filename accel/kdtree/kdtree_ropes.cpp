#include "accel/kdtree/kdtree_ropes.h"

#include <tbb/parallel_invoke.h>

namespace arbor::accel {

std::uint32_t push_rope_down(const KdTree& tree, std::uint32_t rope, int face, const Bounds& box) {
    const int face_axis = face / 2;
    const bool max_face = face & 1;
    while (rope != kd_no_rope) {
        const KdNode n = tree.nodes[rope];
        if (n.is_leaf()) break;
        const int k = n.axis();
        if (k == face_axis) {
            // The node lies wholly beyond the face, so its split is further out: the half next to
            // the face is the left one beyond a max face, the right one beyond a min face.
            rope = max_face ? rope + 1 : n.index();
        } else if (box.hi[k] <= n.split) {
            rope = rope + 1;
        } else if (box.lo[k] >= n.split) {
            rope = n.index();
        } else {
            break;  // the split cuts the face: this is the smallest node holding all of it
        }
    }
    return rope;
}

namespace {

struct RopeBuilder {
    KdTree& tree;

    void visit(std::uint32_t node, const Bounds& box, const std::uint32_t (&ropes)[6], std::uint32_t depth) {
        const KdNode n = tree.nodes[node];
        if (n.is_leaf()) {
            KdLeaf& leaf = tree.leaves[n.index()];
            for (int f = 0; f < 6; ++f) leaf.rope[f] = ropes[f];
            return;
        }
        const int k = n.axis();
        Bounds lb = box, rb = box;
        lb.hi[k] = n.split;
        rb.lo[k] = n.split;
        std::uint32_t lr[6], rr[6];
        for (int f = 0; f < 6; ++f) lr[f] = rr[f] = ropes[f];
        lr[kd_face(k, true)] = n.index();  // beyond the left child's max face: the right child
        rr[kd_face(k, false)] = node + 1;  // beyond the right child's min face: the left child
        for (int f = 0; f < 6; ++f) {
            lr[f] = push_rope_down(tree, lr[f], f, lb);
            rr[f] = push_rope_down(tree, rr[f], f, rb);
        }
        // Leaves are disjoint, so the two halves can be roped in parallel (the result is the same).
        if (depth < 6) {
            tbb::parallel_invoke([&] { visit(node + 1, lb, lr, depth + 1); },
                                 [&] { visit(n.index(), rb, rr, depth + 1); });
        } else {
            visit(node + 1, lb, lr, depth + 1);
            visit(n.index(), rb, rr, depth + 1);
        }
    }
};

}  // namespace

void compute_ropes(KdTree& tree) {
    if (tree.nodes.empty()) return;
    const std::uint32_t none[6] = {kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope};
    RopeBuilder{tree}.visit(0, tree.box, none, 0);
}

}  // namespace arbor::accel
