#include "accel/wide/wide_winding.h"

#include "accel/core/solid_angle_soa.h"
#include "accel/core/winding_walk.h"
#include "accel/util/timer.h"

#include <string>

namespace arbor::accel {

namespace {

/// WideLayout<N> as winding_walk.h reads it: a leaf child's `count` triangles fill consecutive
/// slots from block `child` on (the last block's unused lanes are past them).
template <std::size_t N>
struct WideTree {
    static constexpr std::size_t width = N;
    const WideLayout<N>& l;

    std::size_t nodes() const { return l.nodes.size(); }
    bool root_is_leaf() const { return false; }
    Slots root_slots() const { return {}; }
    std::size_t children(std::uint32_t n) const { return l.nodes[n].children; }
    bool is_leaf(std::uint32_t n, std::size_t c) const { return l.nodes[n].count[c] != 0; }
    std::uint32_t node(std::uint32_t n, std::size_t c) const { return l.nodes[n].child[c]; }
    Slots slots(std::uint32_t n, std::size_t c) const {
        return {l.nodes[n].child[c] * std::uint32_t(N), std::uint32_t(l.nodes[n].count[c])};
    }
    Bounds box(std::uint32_t n, std::size_t c) const {
        const auto& b = l.nodes[n].boxes.b;
        return {{b[0][0][c], b[0][1][c], b[0][2][c]}, {b[1][0][c], b[1][1][c], b[1][2][c]}};
    }
    Vec3f vertex(std::uint32_t slot, int k) const { return l.vertex(slot, k); }
    /// A leaf's triangles block by block, each block's lanes a double batch at a time.
    double leaf_winding(Slots s, const Vec3f& p) const {
        double sum = 0.0;
        for (std::uint32_t done = 0; done < s.count; done += std::uint32_t(N))
            sum += soa_triangles_winding<N>(p, l.blocks[(s.first + done) / N].tris.v, std::min<std::size_t>(N, s.count - done));
        return sum;
    }
};

template <std::size_t N>
class WideWinding final : public WindingTree {
public:
    explicit WideWinding(const WideLayout<N>& layout) : tree_{layout} {
        const Timer timer;
        dipoles_ = make_dipoles(tree_);
        build_ms_ = timer.ms();
        method_ = "wide" + std::to_string(N);
    }
    void winding_numbers(std::span<const Vec3f> points, double beta, std::span<double> out,
                         std::span<double> bound) const override {
        winding_batch(tree_, dipoles_, points, beta, out, bound);
    }
    std::string_view method() const override { return method_; }
    std::size_t memory_bytes() const override { return dipoles_.capacity() * sizeof(DipoleSlots<N>); }

private:
    WideTree<N> tree_;
    std::vector<DipoleSlots<N>> dipoles_;
    std::string method_;
};

}  // namespace

template <std::size_t N>
std::unique_ptr<WindingTree> make_wide_winding(const WideLayout<N>& layout) {
    return std::make_unique<WideWinding<N>>(layout);
}

template std::unique_ptr<WindingTree> make_wide_winding<4>(const WideLayout<4>&);
template std::unique_ptr<WindingTree> make_wide_winding<8>(const WideLayout<8>&);
template std::unique_ptr<WindingTree> make_wide_winding<16>(const WideLayout<16>&);

}  // namespace arbor::accel
