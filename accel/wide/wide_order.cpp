#include "accel/wide/wide_order.h"

#include "accel/util/prefault.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace arbor::accel {

template <std::size_t N> void make_octant_orders(WideLayout<N>& layout) {
    resize_prefaulted(layout.orders, layout.nodes.size() * 8 * N);  // every entry written below
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layout.nodes.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const WideNode<N>& n = layout.nodes[i];
            for (int o = 0; o < 8; ++o) {
                float key[N];
                for (std::size_t c = 0; c < n.children; ++c) {
                    key[c] = 0.0f;
                    for (int k = 0; k < 3; ++k) {
                        const float centre2 = n.boxes.b[0][k][c] + n.boxes.b[1][k][c];
                        key[c] += (o >> k) & 1 ? -centre2 : centre2;
                    }
                }
                // Unused slots first (they never hit), then the children by key, largest (farthest)
                // first; an insertion sort, stable: of equal keys the lower lane ends up nearer.
                std::uint8_t* out = &layout.orders[(i * 8 + std::size_t(o)) * N];
                std::size_t k = 0;
                for (std::size_t c = n.children; c < N; ++c) out[k++] = std::uint8_t(c);
                const std::size_t first = k;
                for (std::size_t c = 0; c < n.children; ++c) {
                    std::size_t j = k++;
                    for (; j > first && !(key[out[j - 1]] > key[c]) ; --j) out[j] = out[j - 1];
                    out[j] = std::uint8_t(c);
                }
            }
        }
    });
}

template void make_octant_orders<4>(WideLayout<4>&);
template void make_octant_orders<8>(WideLayout<8>&);
template void make_octant_orders<16>(WideLayout<16>&);

}  // namespace arbor::accel
