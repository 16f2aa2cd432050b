#include "accel/bvh/bvh2_layout.h"

#include "accel/util/prefault.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>

namespace arbor::accel {

namespace {

/// Subtrees with at least this many interior nodes are converted as two parallel tasks.
constexpr std::uint32_t parallel_nodes = 2048;

class Converter {
public:
    Converter(const BinaryBvh& bvh, const TriangleView& tris, Bvh2Layout& out) : bvh_(bvh), tris_(tris), out_(out) {
        // Children come after their parents, so one backward sweep sees children first.
        const std::size_t n = bvh.nodes.size();
        sub_nodes_.assign(n, 0);
        sub_tris_.assign(n, 0);
        height_.assign(n, 0);
        for (std::size_t i = n; i-- > 0;) {
            const BvhBuildNode& node = bvh.nodes[i];
            if (node.is_leaf()) {
                sub_tris_[i] = node.count;
            } else {
                const std::uint32_t a = node.first, b = node.first + 1;
                sub_nodes_[i] = 1 + sub_nodes_[a] + sub_nodes_[b];
                sub_tris_[i] = sub_tris_[a] + sub_tris_[b];
                height_[i] = 1 + std::max(height_[a], height_[b]);
            }
        }
    }

    void run() {
        if (bvh_.nodes.empty()) return;
        resize_prefaulted(out_.nodes, sub_nodes_[0]);
        const std::size_t tris = sub_tris_[0];
        resize_prefaulted(out_.blocks, (tris + tri_block_width - 1) / tri_block_width);
        resize_prefaulted(out_.prim_ids, out_.blocks.size() * tri_block_width);
        out_.max_depth = height_[0];
        const BvhBuildNode& root = bvh_.nodes[0];
        out_.root_box = root.box;
        if (root.is_leaf()) {
            out_.root_child = 0;
            out_.root_count = root.count;
            emit_leaf(root, 0);
        } else {
            out_.root_child = 0;
            out_.root_count = 0;
            emit(0, 0, 0);
        }
        // Lanes past the last triangle repeat it, so a 4-wide test of the last block is harmless.
        for (std::size_t slot = tris; slot < out_.prim_ids.size(); ++slot)
            write_slot(std::uint32_t(slot), out_.prim_ids[tris - 1]);
    }

private:
    /// Writes interior binary node `i` as flat node `slot`, its triangles from slot `tri` on.
    void emit(std::uint32_t i, std::uint32_t slot, std::uint32_t tri) {
        const BvhBuildNode& node = bvh_.nodes[i];
        Bvh2Node& f = out_.nodes[slot];
        std::uint32_t next_slot = slot + 1, next_tri = tri;
        std::uint32_t child_slot[2] = {0, 0}, child_tri[2] = {0, 0};
        for (int c = 0; c < 2; ++c) {
            const std::uint32_t ci = node.first + std::uint32_t(c);
            const BvhBuildNode& child = bvh_.nodes[ci];
            f.x[c] = child.box.lo.x, f.x[2 + c] = child.box.hi.x;
            f.y[c] = child.box.lo.y, f.y[2 + c] = child.box.hi.y;
            f.z[c] = child.box.lo.z, f.z[2 + c] = child.box.hi.z;
            child_slot[c] = next_slot;
            child_tri[c] = next_tri;
            f.count[c] = child.is_leaf() ? child.count : 0;
            f.child[c] = child.is_leaf() ? next_tri : next_slot;
            next_slot += sub_nodes_[ci];
            next_tri += sub_tris_[ci];
        }
        auto side = [&](int c) {
            const std::uint32_t ci = node.first + std::uint32_t(c);
            const BvhBuildNode& child = bvh_.nodes[ci];
            if (child.is_leaf()) emit_leaf(child, child_tri[c]);
            else emit(ci, child_slot[c], child_tri[c]);
        };
        if (sub_nodes_[i] >= parallel_nodes) tbb::parallel_invoke([&] { side(0); }, [&] { side(1); });
        else side(0), side(1);
    }

    void emit_leaf(const BvhBuildNode& leaf, std::uint32_t slot) {
        for (std::uint32_t j = 0; j < leaf.count; ++j) write_slot(slot + j, bvh_.prim_ids[leaf.first + j]);
    }

    void write_slot(std::uint32_t slot, std::uint32_t tri) {
        TriBlock4& b = out_.blocks[slot / tri_block_width];
        const std::uint32_t l = slot % tri_block_width;
        float (*dst[3])[4] = {b.v0, b.v1, b.v2};
        for (int v = 0; v < 3; ++v) {
            const std::uint32_t i = tris_.indices[3 * std::size_t(tri) + v];
            dst[v][0][l] = tris_.x[i], dst[v][1][l] = tris_.y[i], dst[v][2][l] = tris_.z[i];
        }
        out_.prim_ids[slot] = tri;
    }

    const BinaryBvh& bvh_;
    const TriangleView& tris_;
    Bvh2Layout& out_;
    std::vector<std::uint32_t> sub_nodes_;   ///< interior nodes in the subtree of each binary node
    std::vector<std::uint32_t> sub_tris_;    ///< triangles in the subtree
    std::vector<std::uint32_t> height_;      ///< height of the subtree (leaf = 0)
};

}  // namespace

Bvh2Layout make_bvh2_layout(const BinaryBvh& bvh, const TriangleView& tris) {
    Bvh2Layout out;
    Converter(bvh, tris, out).run();
    return out;
}

std::size_t bvh2_layout_bytes(const BinaryBvh& bvh) {
    // Converter::run's arrays: a node per interior node, a block per tri_block_width triangles and
    // an id per block slot.
    std::size_t interior = 0, tris = 0;
    for (const BvhBuildNode& node : bvh.nodes) {
        if (node.is_leaf()) tris += node.count;
        else ++interior;
    }
    const std::size_t blocks = (tris + tri_block_width - 1) / tri_block_width;
    return interior * sizeof(Bvh2Node) + blocks * sizeof(TriBlock4) +
           blocks * tri_block_width * sizeof(std::uint32_t) + sizeof(Bvh2Layout);
}

}  // namespace arbor::accel
