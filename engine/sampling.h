#pragma once
/// Sampling helpers of the renderer: per-(pixel, sample, dimension) random streams, stratified
/// sub-pixel positions, and the warps from [0,1)^2 to directions and triangle points.
/// Everything here is a pure function of its arguments, so images do not depend on threads.
#include "accel/core/ray.h"

#include <cstdint>
#include <numbers>

namespace arbor::engine {

using accel::Vec3f;

/// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit hash.
inline std::uint64_t mix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// The random numbers of one (seed, pixel, sample): the d-th call of next() returns a value that
/// depends only on (seed, pixel, sample, d). Cheap to copy; no global state.
class SampleStream {
public:
    SampleStream() = default;
    SampleStream(std::uint32_t seed, std::uint32_t pixel, std::uint32_t sample)
        : key_(mix64((std::uint64_t(pixel) << 32 | sample) ^ mix64(seed))) {}

    /// Uniform in [0, 1): 24 random bits, so 1.0 is never returned.
    float next() { return float(mix64(key_ + 0x632BE59BD9B4E019ull * ++dim_) >> 40) * (1.0f / 16777216.0f); }
    std::uint32_t dimension() const { return dim_; }

private:
    std::uint64_t key_ = 0;
    std::uint32_t dim_ = 0;
};

/// Sub-pixel position of sample `s` of `n` in [0,1)^2: the n samples are stratified on a
/// cols x rows grid with cols * rows == n exactly (cols = the largest divisor of n not above
/// sqrt(n)), jittered inside their cell by (u, v). Every cell is used once, so the pixel filter
/// stays a box for any n.
struct PixelStrata {
    int cols = 1, rows = 1;

    explicit PixelStrata(int n) {
        for (int c = 1; c * c <= n; ++c)
            if (n % c == 0) cols = c;
        rows = n / cols;
    }
    void position(int s, float u, float v, float& x, float& y) const {
        x = (float(s % cols) + u) / float(cols);
        y = (float(s / cols) + v) / float(rows);
    }
};

/// Orthonormal basis around unit vector n (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited"); returns t, b with (t, b, n) right-handed.
inline void orthonormal_basis(const Vec3f& n, Vec3f& t, Vec3f& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

/// Cosine-weighted direction in the hemisphere around unit normal n (Malley's method: a uniform
/// disk point lifted to the hemisphere); pdf = cos(theta) / pi. The result is unit length.
inline Vec3f cosine_hemisphere(const Vec3f& n, float u1, float u2) {
    const float r = std::sqrt(u1);
    const float phi = 2.0f * std::numbers::pi_v<float> * u2;
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    Vec3f t, b;
    orthonormal_basis(n, t, b);
    return t * x + b * y + n * z;
}

/// Barycentric coordinates (b1, b2) of a uniform point on a triangle (square-root warp,
/// Shirley & Chiu); the point is (1 - b1 - b2) v0 + b1 v1 + b2 v2.
inline void uniform_triangle(float u1, float u2, float& b1, float& b2) {
    const float s = std::sqrt(u1);
    b1 = s * (1.0f - u2);
    b2 = s * u2;
}

/// Luminance of a linear RGB value (Rec. 709 weights).
inline float luminance(const Vec3f& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool is_black(const Vec3f& c) { return !(c.x > 0.0f || c.y > 0.0f || c.z > 0.0f); }

}  // namespace arbor::engine
