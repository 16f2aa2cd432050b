#include "engine/procedural.h"
#include "winding_check.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace arbor::testing {

namespace {

/// A signed integer of any size, just enough for an exact 3x3 determinant: magnitude in base 2^32
/// limbs, least significant first.
struct BigInt {
    bool negative = false;
    std::vector<std::uint32_t> limbs;

    bool zero() const { return limbs.empty(); }
    void trim() {
        while (!limbs.empty() && limbs.back() == 0) limbs.pop_back();
        if (limbs.empty()) negative = false;
    }
    /// m * 2^shift for an integer |m| < 2^64 and shift >= 0.
    static BigInt of(std::uint64_t m, bool neg, int shift) {
        BigInt r;
        r.negative = neg;
        r.limbs.assign(std::size_t(shift / 32) + 3, 0);
        const unsigned __int128 v = static_cast<unsigned __int128>(m) << (shift % 32);
        for (int k = 0; k < 3; ++k) r.limbs[std::size_t(shift / 32 + k)] = std::uint32_t(v >> (32 * k));
        r.trim();
        return r;
    }
    friend BigInt operator*(const BigInt& x, const BigInt& y) {
        BigInt r;
        r.negative = x.negative != y.negative;
        r.limbs.assign(x.limbs.size() + y.limbs.size(), 0);
        for (std::size_t i = 0; i < x.limbs.size(); ++i) {
            std::uint64_t carry = 0;
            for (std::size_t j = 0; j < y.limbs.size(); ++j) {
                const std::uint64_t t = std::uint64_t(x.limbs[i]) * y.limbs[j] + r.limbs[i + j] + carry;
                r.limbs[i + j] = std::uint32_t(t);
                carry = t >> 32;
            }
            r.limbs[i + y.limbs.size()] = std::uint32_t(carry);
        }
        r.trim();
        return r;
    }
    /// |x| compared with |y|: -1, 0, 1.
    static int compare(const BigInt& x, const BigInt& y) {
        if (x.limbs.size() != y.limbs.size()) return x.limbs.size() < y.limbs.size() ? -1 : 1;
        for (std::size_t i = x.limbs.size(); i-- > 0;)
            if (x.limbs[i] != y.limbs[i]) return x.limbs[i] < y.limbs[i] ? -1 : 1;
        return 0;
    }
    friend BigInt operator+(const BigInt& x, const BigInt& y) {
        BigInt r;
        if (x.negative == y.negative) {  // magnitudes add
            r.negative = x.negative;
            std::uint64_t carry = 0;
            for (std::size_t i = 0; i < std::max(x.limbs.size(), y.limbs.size()); ++i) {
                const std::uint64_t t =
                    std::uint64_t(i < x.limbs.size() ? x.limbs[i] : 0) + (i < y.limbs.size() ? y.limbs[i] : 0) + carry;
                r.limbs.push_back(std::uint32_t(t));
                carry = t >> 32;
            }
            r.limbs.push_back(std::uint32_t(carry));
        } else {  // the larger magnitude minus the smaller, with the larger's sign
            const bool x_big = compare(x, y) >= 0;
            const BigInt& big = x_big ? x : y;
            const BigInt& small = x_big ? y : x;
            r.negative = big.negative;
            std::int64_t borrow = 0;
            for (std::size_t i = 0; i < big.limbs.size(); ++i) {
                std::int64_t t = std::int64_t(big.limbs[i]) - (i < small.limbs.size() ? small.limbs[i] : 0) - borrow;
                borrow = t < 0;
                if (t < 0) t += std::int64_t(1) << 32;
                r.limbs.push_back(std::uint32_t(t));
            }
        }
        r.trim();
        return r;
    }
    friend BigInt operator-(const BigInt& x, BigInt y) {
        y.negative = !y.negative && !y.zero();
        return x + y;
    }
};

/// Whether the triple product of q's rows is exactly 0, in integers (independent of the library's
/// expansion arithmetic): each row entry is an exact difference of floats (long double holds it),
/// so an integer times 2^lo for the smallest lo among them.
bool exactly_coplanar(const long double q[3][3]) {
    int lo = std::numeric_limits<int>::max();
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
            if (q[r][k] != 0.0L) {
                int ex = 0;
                std::frexp(q[r][k], &ex);
                lo = std::min(lo, ex - 64);
            }
    if (lo == std::numeric_limits<int>::max()) return true;  // all zero
    BigInt v[3][3];
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) {
            if (q[r][k] == 0.0L) continue;  // zero (BigInt's default); its exponent would give a negative shift
            int ex = 0;
            const long double m = std::frexp(q[r][k], &ex);  // |m| in [1/2, 1): 64 mantissa bits
            const auto bits = static_cast<std::uint64_t>(std::fabs(std::ldexp(m, 64)));
            v[r][k] = BigInt::of(bits, m < 0.0L, ex - 64 - lo);
        }
    const BigInt det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) +
                       v[0][1] * (v[1][2] * v[2][0] - v[1][0] * v[2][2]) +
                       v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
    return det.zero();
}

}  // namespace

long double oracle_winding(const accel::TriangleView& tris, const accel::Vec3f& p) {
    using L = long double;
    L sum = 0.0L;
    for (std::size_t t = 0; t < tris.triangle_count(); ++t) {
        if (!tris.triangle_is_finite(t)) continue;
        L q[3][3];
        for (int k = 0; k < 3; ++k) {
            const accel::Vec3f c = tris.corner(t, k);
            q[k][0] = L(c.x) - L(p.x), q[k][1] = L(c.y) - L(p.y), q[k][2] = L(c.z) - L(p.z);
        }
        const auto dot = [](const L* a, const L* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
        const L det = q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) +
                      q[0][1] * (q[1][2] * q[2][0] - q[1][0] * q[2][2]) +
                      q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
        // Far from 0 relative to its terms, the long-double value cannot be a rounded 0; near it,
        // integers decide.
        const L perm = std::fabs(q[0][0]) * (std::fabs(q[1][1] * q[2][2]) + std::fabs(q[1][2] * q[2][1])) +
                       std::fabs(q[0][1]) * (std::fabs(q[1][2] * q[2][0]) + std::fabs(q[1][0] * q[2][2])) +
                       std::fabs(q[0][2]) * (std::fabs(q[1][0] * q[2][1]) + std::fabs(q[1][1] * q[2][0]));
        if (!(std::fabs(det) > 1e-12L * perm) && exactly_coplanar(q)) continue;
        const L la = std::sqrt(dot(q[0], q[0])), lb = std::sqrt(dot(q[1], q[1])), lc = std::sqrt(dot(q[2], q[2]));
        const L den = la * lb * lc + dot(q[0], q[1]) * lc + dot(q[0], q[2]) * lb + dot(q[1], q[2]) * la;
        sum += std::atan2(det, den);
    }
    return sum / (2.0L * std::numbers::pi_v<long double>);
}

engine::Mesh grid_box(float lo, float hi, int n) {
    engine::Mesh m;
    // One vertex per lattice point of the surface, shared by the faces that meet there.
    const auto at = [&](int i) { return lo + (hi - lo) * float(i) / float(n); };
    std::vector<std::int64_t> id(std::size_t((n + 1) * (n + 1) * (n + 1)), -1);
    const auto vertex = [&](int i, int j, int k) {
        std::int64_t& v = id[std::size_t((i * (n + 1) + j) * (n + 1) + k)];
        if (v < 0) v = m.add_vertex({at(i), at(j), at(k)});
        return std::uint32_t(v);
    };
    // Face `axis` at side s (0: lo, 1: hi); (u, w) the other two axes in cyclic order, so that
    // u x w points along +axis; the lo side is wound the other way round.
    for (int axis = 0; axis < 3; ++axis)
        for (int s = 0; s < 2; ++s)
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    std::uint32_t c[4];
                    const int corners[4][2] = {{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}};
                    for (int k = 0; k < 4; ++k) {
                        int ijk[3];
                        ijk[axis] = s * n;
                        ijk[(axis + 1) % 3] = corners[k][0];
                        ijk[(axis + 2) % 3] = corners[k][1];
                        c[k] = vertex(ijk[0], ijk[1], ijk[2]);
                    }
                    if (s == 1) {
                        m.add_triangle(c[0], c[1], c[2]);
                        m.add_triangle(c[0], c[2], c[3]);
                    } else {
                        m.add_triangle(c[0], c[2], c[1]);
                        m.add_triangle(c[0], c[3], c[2]);
                    }
                }
    m.compute_bounds();
    return m;
}

engine::Mesh flipped(const engine::Mesh& m) {
    engine::Mesh out = m;
    for (std::size_t t = 0; t < out.triangle_count(); ++t) std::swap(out.indices[3 * t + 1], out.indices[3 * t + 2]);
    return out;
}

engine::Mesh doubled(const engine::Mesh& m) {
    engine::Mesh out = m;
    out.indices.insert(out.indices.end(), m.indices.begin(), m.indices.end());
    return out;
}

engine::Mesh without_faces(const engine::Mesh& m, unsigned permille, std::uint32_t seed) {
    engine::Mesh out;
    out.x = m.x, out.y = m.y, out.z = m.z;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        if ((std::uint64_t(t) * 2654435761u + seed) % 1000 >= permille)
            out.indices.insert(out.indices.end(), m.indices.begin() + std::ptrdiff_t(3 * t),
                               m.indices.begin() + std::ptrdiff_t(3 * t + 3));
    out.compute_bounds();
    return out;
}

engine::Mesh moved(const engine::Mesh& m, float scale, accel::Vec3f offset) {
    engine::Mesh out;
    out.indices = m.indices;
    for (std::size_t i = 0; i < m.vertex_count(); ++i)
        out.add_vertex({m.x[i] * scale + offset.x, m.y[i] * scale + offset.y, m.z[i] * scale + offset.z});
    out.compute_bounds();
    return out;
}

engine::Mesh slivers() {
    engine::Mesh m = engine::make_icosphere({0, 0, 0}, 0.5f, 2);
    for (int i = 0; i < 64; ++i) {
        const float a = 0.1f * float(i), r = 1.0f + 0.02f * float(i);
        const accel::Vec3f p{r * std::cos(a), r * std::sin(a), 0.05f * float(i % 7) - 0.15f};
        const accel::Vec3f e{-std::sin(a), std::cos(a), 0.3f};
        const accel::Vec3f up{0.0f, 0.0f, 1e-6f};
        const std::uint32_t b = std::uint32_t(m.vertex_count());
        m.add_vertex(p);
        m.add_vertex(p + e);
        m.add_vertex(p + e * 0.5f + up);  // 1e-6 off the midpoint: a sliver
        m.add_vertex(p + e * 1e-7f);      // a needle: two corners 1e-7 apart
        m.add_triangle(b, b + 1, b + 2);
        m.add_triangle(b, b + 3, b + 1);
    }
    m.compute_bounds();
    return m;
}

Reference reference(const accel::TriangleView& tris, const std::vector<accel::Vec3f>& points) {
    Reference r;
    r.exact.resize(points.size());
    accel::make_exact_winding(tris)->winding_numbers(points, accel::default_winding_beta, r.exact);
    for (const accel::Vec3f& p : points) r.oracle.push_back(double(oracle_winding(tris, p)));
    return r;
}

TreeCheck check_tree(const accel::WindingTree& tree, const Reference& ref, const std::vector<accel::Vec3f>& points,
                     double beta) {
    TreeCheck r;
    std::vector<double> w(points.size()), bound(points.size());
    tree.winding_numbers(points, beta, w, bound);
    for (std::size_t i = 0; i < points.size(); ++i) {
        r.worst_vs_oracle = std::max(r.worst_vs_oracle, std::fabs(w[i] - ref.oracle[i]));
        r.worst_bound_excess = std::max(r.worst_bound_excess, std::fabs(w[i] - ref.exact[i]) - bound[i]);
        r.largest_bound = std::max(r.largest_bound, bound[i]);
    }
    return r;
}

TreeCheck check_tree(const accel::WindingTree& tree, const accel::TriangleView& tris,
                     const std::vector<accel::Vec3f>& points, double beta) {
    return check_tree(tree, reference(tris, points), points, beta);
}

}  // namespace arbor::testing
