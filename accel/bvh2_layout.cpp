#include "accel/bvh2_layout.h"

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
        sub_blocks_.assign(n, 0);
        height_.assign(n, 0);
        for (std::size_t i = n; i-- > 0;) {
            const BvhBuildNode& node = bvh.nodes[i];
            if (node.is_leaf()) {
                sub_blocks_[i] = (node.count + tri_block_width - 1) / tri_block_width;
            } else {
                const std::uint32_t a = node.first, b = node.first + 1;
                sub_nodes_[i] = 1 + sub_nodes_[a] + sub_nodes_[b];
                sub_blocks_[i] = sub_blocks_[a] + sub_blocks_[b];
                height_[i] = 1 + std::max(height_[a], height_[b]);
            }
        }
    }

    void run() {
        if (bvh_.nodes.empty()) return;
        out_.nodes.resize(sub_nodes_[0]);
        out_.blocks.resize(sub_blocks_[0]);
        out_.prim_ids.resize(std::size_t(sub_blocks_[0]) * tri_block_width);
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
    }

private:
    /// Writes interior binary node `i` as flat node `slot`, its triangles from block `block` on.
    void emit(std::uint32_t i, std::uint32_t slot, std::uint32_t block) {
        const BvhBuildNode& node = bvh_.nodes[i];
        Bvh2Node& f = out_.nodes[slot];
        std::uint32_t next_slot = slot + 1, next_block = block;
        std::uint32_t child_slot[2] = {0, 0}, child_block[2] = {0, 0};
        for (int c = 0; c < 2; ++c) {
            const std::uint32_t ci = node.first + std::uint32_t(c);
            const BvhBuildNode& child = bvh_.nodes[ci];
            f.x[c] = child.box.lo.x, f.x[2 + c] = child.box.hi.x;
            f.y[c] = child.box.lo.y, f.y[2 + c] = child.box.hi.y;
            f.z[c] = child.box.lo.z, f.z[2 + c] = child.box.hi.z;
            child_slot[c] = next_slot;
            child_block[c] = next_block;
            f.count[c] = child.is_leaf() ? child.count : 0;
            f.child[c] = child.is_leaf() ? next_block * tri_block_width : next_slot;
            next_slot += sub_nodes_[ci];
            next_block += sub_blocks_[ci];
        }
        auto side = [&](int c) {
            const std::uint32_t ci = node.first + std::uint32_t(c);
            const BvhBuildNode& child = bvh_.nodes[ci];
            if (child.is_leaf()) emit_leaf(child, child_block[c]);
            else emit(ci, child_slot[c], child_block[c]);
        };
        if (sub_nodes_[i] >= parallel_nodes) tbb::parallel_invoke([&] { side(0); }, [&] { side(1); });
        else side(0), side(1);
    }

    void emit_leaf(const BvhBuildNode& leaf, std::uint32_t block) {
        for (std::uint32_t j = 0; j < leaf.count; j += tri_block_width) {
            TriBlock4& b = out_.blocks[block + j / tri_block_width];
            for (std::uint32_t l = 0; l < tri_block_width; ++l) {
                const std::uint32_t k = std::min(j + l, leaf.count - 1);  // pad with the last triangle
                const std::uint32_t tri = bvh_.prim_ids[leaf.first + k];
                for (int v = 0; v < 3; ++v) {
                    const Vec3f p = tris_.corner(tri, v);
                    auto& dst = v == 0 ? b.v0 : (v == 1 ? b.v1 : b.v2);
                    dst[0][l] = p.x, dst[1][l] = p.y, dst[2][l] = p.z;
                }
                out_.prim_ids[std::size_t(block) * tri_block_width + j + l] = tri;
            }
        }
    }

    const BinaryBvh& bvh_;
    const TriangleView& tris_;
    Bvh2Layout& out_;
    std::vector<std::uint32_t> sub_nodes_;   ///< interior nodes in the subtree of each binary node
    std::vector<std::uint32_t> sub_blocks_;  ///< triangle blocks in the subtree
    std::vector<std::uint32_t> height_;      ///< height of the subtree (leaf = 0)
};

}  // namespace

Bvh2Layout make_bvh2_layout(const BinaryBvh& bvh, const TriangleView& tris) {
    Bvh2Layout out;
    Converter(bvh, tris, out).run();
    return out;
}

}  // namespace arbor::accel
