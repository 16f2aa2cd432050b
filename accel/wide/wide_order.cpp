#include "accel/wide/wide_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>

#include "simd/simd.h"  // XSIMD_WITH_AVX512F
#if XSIMD_WITH_AVX512F
#include <immintrin.h>
#endif

#include "accel/util/prefault.h"

namespace arbor::accel {

namespace {

/// The children's keys for octant o (wide_order.h): d . (lo + hi) summed axis by axis.
template <std::size_t N>
void octant_keys(const WideNode<N>& n, int o, float key[N]) {
    for (std::size_t c = 0; c < n.children; ++c) {
        key[c] = 0.0f;
        for (int k = 0; k < 3; ++k) {
            const float centre2 = n.boxes.b[0][k][c] + n.boxes.b[1][k][c];
            key[c] += (o >> k) & 1 ? -centre2 : centre2;
        }
    }
}

/// Octant order by `key` into out[0, N): unused slots first (they never hit), then the children
/// by key, largest (farthest) first; an insertion sort, stable: of equal keys the lower lane ends
/// up nearer. Returns where the children start.
template <std::size_t N>
std::size_t sort_octant(const WideNode<N>& n, const float key[N], std::uint8_t* out) {
    std::size_t k = 0;
    for (std::size_t c = n.children; c < N; ++c) out[k++] = std::uint8_t(c);
    const std::size_t first = k;
    for (std::size_t c = 0; c < n.children; ++c) {
        std::size_t j = k++;
        for (; j > first && !(key[out[j - 1]] > key[c]); --j) out[j] = out[j - 1];
        out[j] = std::uint8_t(c);
    }
    return first;
}

/// The order of the opposite octant (every sign flipped: each key negated, exactly) from `order`,
/// whose children start at `first`: sort_octant's answer on the negated keys, which is the
/// children reversed (far becomes near) with each run of equal keys turned back (the lower lane
/// stays nearer). For keys without NaN (with NaN sort_octant's order is not a sort: not used).
template <std::size_t N>
void opposite_octant(const float key[N], const std::uint8_t* order, std::size_t first, std::uint8_t* out) {
    for (std::size_t j = 0; j < first; ++j) out[j] = order[j];
    std::size_t j = first;
    for (std::size_t e = N; e > first;) {
        // The run of equal keys ending at e - 1 (as read from the far end of `order`).
        std::size_t b = e - 1;
        while (b > first && key[order[b - 1]] == key[order[e - 1]]) --b;
        for (std::size_t i = b; i < e; ++i) out[j++] = order[i];
        e = b;
    }
}

#if XSIMD_WITH_AVX512F
/// For 16-wide nodes: the orders of octant o (into `out`) and of its opposite, 7 - o (into
/// `opposite`), from o's keys without NaN, as sort_octant gives them, by counting with vector
/// compares: child c goes after the children with a larger key (the opposite octant: a smaller
/// one) and after the higher lanes of an equal key. No data-dependent branch (the insertion sort's
/// were a third of a refit's time).
inline void rank_octants16(std::size_t children, const float key[16], std::uint8_t* out, std::uint8_t* opposite) {
    const std::size_t first = 16 - children;
    const auto live = __mmask16((1u << children) - 1u);
    const __m512 k = _mm512_maskz_loadu_ps(live, key);
    for (std::size_t c = children; c < 16; ++c) out[c - children] = opposite[c - children] = std::uint8_t(c);
    for (std::size_t c = 0; c < children; ++c) {
        const __m512 kc = _mm512_set1_ps(key[c]);
        const auto above = __mmask16(live & ~((2u << c) - 1u));
        const auto larger = unsigned(std::popcount(unsigned(_mm512_mask_cmp_ps_mask(live, k, kc, _CMP_GT_OQ))));
        const auto smaller = unsigned(std::popcount(unsigned(_mm512_mask_cmp_ps_mask(live, k, kc, _CMP_LT_OQ))));
        const auto tied = unsigned(std::popcount(unsigned(_mm512_mask_cmp_ps_mask(above, k, kc, _CMP_EQ_OQ))));
        out[first + larger + tied] = std::uint8_t(c);
        opposite[first + smaller + tied] = std::uint8_t(c);
    }
}
#endif

}  // namespace

template <std::size_t N>
void make_octant_orders(WideLayout<N>& layout) {
    resize_prefaulted(layout.orders, layout.nodes.size() * 8 * N);  // every entry written below
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layout.nodes.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const WideNode<N>& n = layout.nodes[i];
            std::uint8_t* orders = &layout.orders[i * 8 * N];
            // Octants o and 7 - o have opposite keys: four sorts give the eight orders.
            for (int o = 0; o < 4; ++o) {
                float key[N];
                octant_keys(n, o, key);
                bool nan = false;
                for (std::size_t c = 0; c < n.children; ++c) nan |= std::isnan(key[c]);
#if XSIMD_WITH_AVX512F
                if constexpr (N == 16) {
                    if (!nan) {
                        rank_octants16(n.children, key, orders + std::size_t(o) * N, orders + std::size_t(7 - o) * N);
                        continue;
                    }
                }
#endif
                const std::size_t first = sort_octant(n, key, orders + std::size_t(o) * N);
                if (!nan) {
                    opposite_octant<N>(key, orders + std::size_t(o) * N, first, orders + std::size_t(7 - o) * N);
                } else {
                    octant_keys(n, 7 - o, key);
                    sort_octant(n, key, orders + std::size_t(7 - o) * N);
                }
            }
        }
    });
}

template void make_octant_orders<4>(WideLayout<4>&);
template void make_octant_orders<8>(WideLayout<8>&);
template void make_octant_orders<16>(WideLayout<16>&);

}  // namespace arbor::accel
