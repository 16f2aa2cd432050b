#pragma once
/// Viridis, the perceptually uniform colour map of matplotlib (Smith and van der Walt 2015; its
/// 256-entry definition is matplotlib's `_cm_listed.py`, CC0): its lightness rises steadily from
/// dark blue to yellow, so equal steps of cost read as equal steps of colour, also in grey and for
/// the common colour-vision deficiencies. Here as 33 of those entries (every 8th, as 8-bit sRGB)
/// with linear interpolation between them: at most 1.7/255 from the full table.
#include <array>
#include <cstdint>

namespace arbor::engine {

/// The colour of v in [0, 1] (clamped; NaN gives the colour of 0), 8-bit sRGB.
std::array<std::uint8_t, 3> viridis(float v);

}  // namespace arbor::engine
