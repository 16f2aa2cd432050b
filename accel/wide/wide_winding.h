#pragma once
/// Winding numbers on an N-wide layout (WideLayout<N>), the one every BVH built for the SIMD paths
/// has: the adapter winding_walk.h reads, and the tree over the layout with one dipole per child
/// box. Compiled once, outside the kernel sets (the layout's arrays are plain floats, the same in
/// every set), and reached from WideBvhAccel<N>::make_winding_tree.
#include "accel/core/winding_tree.h"
#include "accel/wide/wide_layout.h"

#include <memory>

namespace arbor::accel {

/// A winding tree over `layout` (which must outlive it): one dipole per used child slot, computed
/// here.
template <std::size_t N>
std::unique_ptr<WindingTree> make_wide_winding(const WideLayout<N>& layout);

extern template std::unique_ptr<WindingTree> make_wide_winding<4>(const WideLayout<4>&);
extern template std::unique_ptr<WindingTree> make_wide_winding<8>(const WideLayout<8>&);
extern template std::unique_ptr<WindingTree> make_wide_winding<16>(const WideLayout<16>&);

}  // namespace arbor::accel
