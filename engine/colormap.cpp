#include "engine/colormap.h"

#include <cmath>

namespace arbor::engine {

namespace {
/// Entries 0, 8, 16, ..., 248, 255 of matplotlib's viridis, rounded to 8 bits.
constexpr std::uint8_t table[33][3] = {
    {68, 1, 84},    {71, 13, 96},   {72, 24, 106},  {72, 35, 116},  {71, 45, 123},  {69, 55, 129},
    {66, 64, 134},  {62, 73, 137},  {59, 82, 139},  {55, 91, 141},  {51, 99, 141},  {47, 107, 142},
    {44, 114, 142}, {41, 122, 142}, {38, 130, 142}, {35, 137, 142}, {33, 145, 140}, {31, 151, 139},
    {31, 159, 136}, {33, 166, 133}, {39, 173, 129}, {49, 181, 123}, {61, 188, 116}, {76, 194, 108},
    {92, 200, 99},  {110, 206, 88}, {129, 211, 77}, {149, 216, 64}, {170, 220, 50}, {192, 223, 37},
    {213, 226, 26}, {234, 229, 26}, {253, 231, 37},
};
}  // namespace

std::array<std::uint8_t, 3> viridis(float v) {
    if (!(v > 0.0f)) v = 0.0f;
    if (v > 1.0f) v = 1.0f;
    // Entry k sits at position k * 8 / 255 on [0, 1], except the last one (255 / 255).
    const float x = v * 255.0f / 8.0f;
    int k = int(x);
    if (k > 31) k = 31;
    const float x1 = k == 31 ? 255.0f / 8.0f : float(k + 1);
    const float f = (x - float(k)) / (x1 - float(k));
    std::array<std::uint8_t, 3> out;
    for (int c = 0; c < 3; ++c)
        out[std::size_t(c)] = std::uint8_t(std::lround(float(table[k][c]) + f * float(table[k + 1][c] - table[k][c])));
    return out;
}

}  // namespace arbor::engine
