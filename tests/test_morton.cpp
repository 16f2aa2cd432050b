// Morton codes: known values, the portable and pdep encoders against a bit-by-bit reference,
// ordering properties, and the quantizer's degenerate boxes (zero extent, +-FLT_MAX, NaN).
#include "accel/lbvh/morton.h"

#include <doctest/doctest.h>

#include <cfloat>
#include <limits>
#include <random>

using namespace arbor;
using accel::Bounds;
using accel::MortonQuantizer;
using accel::Vec3f;

namespace {

/// Reference interleave: bit i of x goes to bit 3i+2, of y to 3i+1, of z to 3i.
std::uint64_t interleave_reference(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits) {
    std::uint64_t code = 0;
    for (int i = 0; i < bits; ++i) {
        code |= std::uint64_t((x >> i) & 1u) << (3 * i + 2);
        code |= std::uint64_t((y >> i) & 1u) << (3 * i + 1);
        code |= std::uint64_t((z >> i) & 1u) << (3 * i);
    }
    return code;
}

}  // namespace

TEST_CASE("morton: known values") {
    CHECK(accel::morton_encode30(0, 0, 0) == 0u);
    CHECK(accel::morton_encode30(1, 0, 0) == 4u);
    CHECK(accel::morton_encode30(0, 1, 0) == 2u);
    CHECK(accel::morton_encode30(0, 0, 1) == 1u);
    CHECK(accel::morton_encode30(3, 0, 0) == 0b100100u);
    CHECK(accel::morton_encode30(1023, 1023, 1023) == (1u << 30) - 1u);
    CHECK(accel::morton_encode30(1024, 0, 0) == 0u);  // bits above 10 are ignored
    CHECK(accel::morton_encode63(0, 0, 1) == 1u);
    CHECK(accel::morton_encode63(1u << 20, 0, 0) == std::uint64_t(1) << 62);
    CHECK(accel::morton_encode63(0x1fffff, 0x1fffff, 0x1fffff) == (std::uint64_t(1) << 63) - 1u);
    static_assert(accel::morton_encode30_portable(5, 3, 6) == 0b101'011'110u);
}

TEST_CASE("morton: portable and pdep encoders agree with the bit-by-bit reference") {
    std::mt19937 rng(1);
    for (int i = 0; i < 20000; ++i) {
        const std::uint32_t x = rng(), y = rng(), z = rng();
        const std::uint32_t c30 = accel::morton_encode30_portable(x, y, z);
        const std::uint64_t c63 = accel::morton_encode63_portable(x, y, z);
        REQUIRE(c30 == interleave_reference(x & 0x3ff, y & 0x3ff, z & 0x3ff, 10));
        REQUIRE(c63 == interleave_reference(x & 0x1fffff, y & 0x1fffff, z & 0x1fffff, 21));
        REQUIRE(accel::morton_encode30(x, y, z) == c30);
        REQUIRE(accel::morton_encode63(x, y, z) == c63);
#if defined(__BMI2__)
        REQUIRE(accel::morton_encode30_pdep(x & 0x3ff, y & 0x3ff, z & 0x3ff) == c30);
        REQUIRE(accel::morton_encode63_pdep(x & 0x1fffff, y & 0x1fffff, z & 0x1fffff) == c63);
#endif
    }
}

TEST_CASE("morton: codes grow with each coordinate, and the high bits order by the top cell bit") {
    std::mt19937 rng(2);
    for (int i = 0; i < 5000; ++i) {
        const std::uint32_t x = rng() & 0x1fffff, y = rng() & 0x1fffff, z = rng() & 0x1fffff;
        const std::uint32_t dx = 1 + rng() % 1000;
        if (x + dx <= 0x1fffff) CHECK(accel::morton_encode63(x + dx, y, z) > accel::morton_encode63(x, y, z));
        if (y + dx <= 0x1fffff) CHECK(accel::morton_encode63(x, y + dx, z) > accel::morton_encode63(x, y, z));
        if (z + dx <= 0x1fffff) CHECK(accel::morton_encode63(x, y, z + dx) > accel::morton_encode63(x, y, z));
        // The top code bit is the top x bit: points in the upper half in x come after all others.
        CHECK(((accel::morton_encode63(x, y, z) >> 62) & 1u) == (x >> 20));
    }
}

TEST_CASE("morton: quantizer maps the box to [0, 2^bits - 1] and is monotone") {
    const Bounds box{{-1, 2, 10}, {3, 4, 10.5f}};
    for (int bits : {10, 21}) {
        const MortonQuantizer q(box, bits);
        const std::uint32_t top = (1u << bits) - 1u;
        CHECK(q.cell(-1.0f, 0) == 0u);
        CHECK(q.cell(3.0f, 0) == top);
        CHECK(q.cell(1.0f, 0) == 1u << (bits - 1));  // the middle starts the upper half
        CHECK(q.cell(-100.0f, 0) == 0u);             // outside: clamped
        CHECK(q.cell(100.0f, 0) == top);
        std::mt19937 rng{std::uint32_t(bits)};
        std::uniform_real_distribution<float> u(-1.5f, 3.5f);
        for (int i = 0; i < 2000; ++i) {
            float a = u(rng), b = u(rng);
            if (a > b) std::swap(a, b);
            CHECK(q.cell(a, 0) <= q.cell(b, 0));
            CHECK(q.cell(a, 0) <= top);
        }
    }
    const MortonQuantizer q10(box, 10);
    CHECK(q10.code30({3, 4, 10.5f}) == (1u << 30) - 1u);
    CHECK(q10.code30({-1, 2, 10}) == 0u);
    const MortonQuantizer q21(box, 21);
    CHECK(q21.code63({3, 4, 10.5f}) == (std::uint64_t(1) << 63) - 1u);
}

TEST_CASE("morton: zero-extent axes, empty boxes and NaN map to cell 0 without dividing by zero") {
    const Bounds flat{{0, 5, -2}, {1, 5, -2}};  // y and z have zero extent
    const MortonQuantizer q(flat, 21);
    CHECK(q.cell(5.0f, 1) == 0u);
    CHECK(q.cell(-2.0f, 2) == 0u);
    CHECK(q.cell(1e30f, 1) == 0u);
    CHECK(q.cell(1.0f, 0) == (1u << 21) - 1u);
    CHECK(q.code63({0.5f, 5, -2}) == std::uint64_t(1) << 62);  // only x contributes
    const Bounds point{{7, 7, 7}, {7, 7, 7}};
    CHECK(MortonQuantizer(point, 10).code30({7, 7, 7}) == 0u);
    const Bounds empty;  // lo = +inf, hi = -inf
    CHECK(MortonQuantizer(empty, 10).code30({1, 2, 3}) == 0u);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(MortonQuantizer(flat, 21).cell(nan, 0) == 0u);
}

TEST_CASE("morton: boxes spanning +-FLT_MAX and tiny boxes do not overflow") {
    const Bounds huge{{-FLT_MAX, -3e38f, -FLT_MAX}, {FLT_MAX, 3e38f, FLT_MAX}};
    for (int bits : {10, 21}) {
        const MortonQuantizer q(huge, bits);
        const std::uint32_t top = (1u << bits) - 1u;
        CHECK(q.cell(-FLT_MAX, 0) == 0u);
        CHECK(q.cell(FLT_MAX, 0) == top);
        // Interior points: the scale 2^bits / extent is rounded, so allow one cell of slack.
        const auto near = [](std::uint32_t cell, std::uint32_t expect) { return cell == expect || cell + 1 == expect; };
        CHECK(near(q.cell(0.0f, 0), 1u << (bits - 1)));
        CHECK(q.cell(-3e38f, 1) == 0u);
        CHECK(q.cell(3e38f, 1) == top);
        CHECK(near(q.cell(3e38f * 0.5f, 1), 3u << (bits - 2)));
        CHECK(q.cell(std::numeric_limits<float>::infinity(), 0) == top);  // clamped, not UB
    }
    // A box of denormal width: the scale is huge but finite in double.
    const float d = std::numeric_limits<float>::denorm_min();
    const Bounds tiny{{0, 0, 0}, {4 * d, 4 * d, 4 * d}};
    const MortonQuantizer q(tiny, 10);
    CHECK(q.cell(0.0f, 0) == 0u);
    CHECK(q.cell(2 * d, 0) == 512u);
    CHECK(q.cell(4 * d, 0) == 1023u);
}
