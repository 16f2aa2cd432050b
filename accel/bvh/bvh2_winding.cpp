#include "accel/bvh/bvh2_winding.h"

#include "accel/bvh/bvh_build.h"
#include "accel/core/winding_walk.h"
#include "accel/util/timer.h"

#include <string>

namespace arbor::accel {

namespace {

/// Bvh2Layout as winding_walk.h reads it: two slots per node; a leaf child's slots are
/// [child, child + count).
struct Bvh2Tree {
    static constexpr std::size_t width = 2;
    const Bvh2Layout& l;

    std::size_t nodes() const { return l.empty() || l.root_count != 0 ? 0 : l.nodes.size(); }
    bool root_is_leaf() const { return !l.empty() && l.root_count != 0; }
    Slots root_slots() const { return {l.root_child, l.root_count}; }
    std::size_t children(std::uint32_t) const { return 2; }
    bool is_leaf(std::uint32_t n, std::size_t c) const { return l.nodes[n].count[c] != 0; }
    std::uint32_t node(std::uint32_t n, std::size_t c) const { return l.nodes[n].child[c]; }
    Slots slots(std::uint32_t n, std::size_t c) const { return {l.nodes[n].child[c], l.nodes[n].count[c]}; }
    Bounds box(std::uint32_t n, std::size_t c) const {
        const Bvh2Node& b = l.nodes[n];
        return {{b.x[c], b.y[c], b.z[c]}, {b.x[2 + c], b.y[2 + c], b.z[2 + c]}};
    }
    Vec3f vertex(std::uint32_t slot, int k) const { return l.vertex(slot, k); }
};

class Bvh2Winding final : public WindingTree {
public:
    /// Over `layout`, or over `owned` (then `layout` is *owned`).
    Bvh2Winding(const Bvh2Layout& layout, std::unique_ptr<Bvh2Layout> owned, double prior_ms)
        : owned_(std::move(owned)), tree_{layout} {
        const Timer timer;
        dipoles_ = make_dipoles(tree_);
        build_ms_ = prior_ms + timer.ms();
        method_ = owned_ ? "bvh2 (internal)" : "bvh2";
    }
    void winding_numbers(std::span<const Vec3f> points, double beta, std::span<double> out,
                         std::span<double> bound) const override {
        winding_batch(tree_, dipoles_, points, beta, out, bound);
    }
    std::string_view method() const override { return method_; }
    std::size_t memory_bytes() const override {
        return dipoles_.capacity() * sizeof(DipoleSlots<2>) + (owned_ ? owned_->memory_bytes() : 0);
    }

private:
    std::unique_ptr<Bvh2Layout> owned_;
    Bvh2Tree tree_;
    std::vector<DipoleSlots<2>> dipoles_;
    std::string method_;
};

}  // namespace

std::unique_ptr<WindingTree> make_bvh2_winding(const Bvh2Layout& layout) {
    return std::make_unique<Bvh2Winding>(layout, nullptr, 0.0);
}

std::unique_ptr<WindingTree> make_internal_winding(const TriangleView& tris) {
    const Timer timer;
    BvhBuildConfig cfg;
    cfg.max_leaf_size = 4;
    const BinaryBvh bvh = build_bvh_sah(make_prim_refs(tris), cfg);
    auto layout = std::make_unique<Bvh2Layout>(make_bvh2_layout(bvh, tris));
    const Bvh2Layout& ref = *layout;
    return std::make_unique<Bvh2Winding>(ref, std::move(layout), timer.ms());
}

}  // namespace arbor::accel
