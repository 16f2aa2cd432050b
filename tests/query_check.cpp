#include "query_check.h"
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"

#include <bit>
#include <cmath>
#include <numbers>
#include <random>

namespace arbor::testing {

std::vector<NamedAccel> query_structures(const accel::TriangleView& v, bool every_width) {
    std::vector<NamedAccel> out;
    out.push_back({"brute", accel::make_accel(accel::AccelKind::brute, v)});
    out.push_back({"kdtree", accel::make_accel(accel::AccelKind::kdtree, v)});
    std::vector<std::uint32_t> widths;
    if (every_width) {
        for (std::uint32_t w : {4u, 8u, 16u})
            if (accel::wide_width_supported(w)) widths.push_back(w);
    } else {
        widths.push_back(accel::default_wide_width());
    }
    for (accel::AccelKind kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
        const std::string name(accel::to_string(kind));
        for (std::uint32_t w : widths) {
            accel::BuildConfig cfg;
            cfg.layouts = accel::Layouts::simd;
            cfg.wide.width = w;
            out.push_back({name + "/w" + std::to_string(w), accel::make_accel(kind, v, cfg)});
        }
        accel::BuildConfig cfg;
        cfg.layouts = accel::Layouts::scalar;
        out.push_back({name + "/scalar", accel::make_accel(kind, v, cfg)});
    }
    return out;
}

std::vector<accel::Vec3f> query_points(const engine::Mesh& m, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<accel::Vec3f> out;
    const std::size_t tris = m.triangle_count();
    std::uniform_int_distribution<std::size_t> pick(0, tris - 1);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const auto corner = [&](std::size_t t, int k) { return m.view().corner(t, k); };
    for (std::size_t i = 0; i < n; ++i) {  // on the surface
        const std::size_t t = pick(rng);
        float a = u01(rng), b = u01(rng);
        if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
        out.push_back(corner(t, 0) * (1.0f - a - b) + corner(t, 1) * a + corner(t, 2) * b);
    }
    for (std::size_t i = 0; i < n; ++i) out.push_back(corner(pick(rng), int(i % 3)));  // vertices
    for (std::size_t i = 0; i < n; ++i) {  // edges: midpoints and points 1/8 along
        const std::size_t t = pick(rng);
        const int k = int(i % 3);
        const float f = i % 2 ? 0.5f : 0.125f;
        out.push_back(corner(t, k) * (1.0f - f) + corner(t, (k + 1) % 3) * f);
    }
    accel::Bounds grown = m.bounds;
    const accel::Vec3f ext = grown.extent();
    grown.lo -= ext * 0.1f, grown.hi += ext * 0.1f;
    for (std::size_t i = 0; i < n; ++i)  // inside the grown box
        out.push_back({grown.lo.x + u01(rng) * (grown.hi.x - grown.lo.x), grown.lo.y + u01(rng) * (grown.hi.y - grown.lo.y),
                       grown.lo.z + u01(rng) * (grown.hi.z - grown.lo.z)});
    const float diag = simd::length(ext);
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (std::size_t i = 0; i < n; ++i) {  // far away
        const accel::Vec3f d = simd::normalize(accel::Vec3f{g(rng), g(rng), g(rng)});
        out.push_back(m.bounds.center() + d * (diag * std::pow(1000.0f, u01(rng))));
    }
    return out;
}

double winding_number(const engine::Mesh& m, const accel::Vec3f& p) {
    // Van Oosterom & Strackee (1983): the solid angle of triangle (a, b, c) seen from the origin is
    // 2 atan2(a . (b x c), |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
    double sum = 0.0;
    const auto v = m.view();
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        double q[3][3];
        for (int k = 0; k < 3; ++k) {
            const accel::Vec3f c = v.corner(t, k);
            q[k][0] = double(c.x) - p.x, q[k][1] = double(c.y) - p.y, q[k][2] = double(c.z) - p.z;
        }
        const auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
        const double la = std::sqrt(dot(q[0], q[0])), lb = std::sqrt(dot(q[1], q[1])), lc = std::sqrt(dot(q[2], q[2]));
        const double cx = q[1][1] * q[2][2] - q[1][2] * q[2][1], cy = q[1][2] * q[2][0] - q[1][0] * q[2][2],
                     cz = q[1][0] * q[2][1] - q[1][1] * q[2][0];
        const double det = q[0][0] * cx + q[0][1] * cy + q[0][2] * cz;
        const double den = la * lb * lc + dot(q[0], q[1]) * lc + dot(q[0], q[2]) * lb + dot(q[1], q[2]) * la;
        sum += 2.0 * std::atan2(det, den);
    }
    return sum / (4.0 * std::numbers::pi);
}

namespace {
class ListSink final : public accel::HitSink {
public:
    explicit ListSink(std::vector<std::vector<accel::Hit>>& out) : out_(out) {}
    void take(std::size_t i, std::span<accel::Hit> hits) override { out_[i].assign(hits.begin(), hits.end()); }

private:
    std::vector<std::vector<accel::Hit>>& out_;
};
}  // namespace

std::vector<std::vector<accel::Hit>> all_hits(const accel::Accel& a, const std::vector<accel::Ray>& rays) {
    std::vector<std::vector<accel::Hit>> out(rays.size());
    ListSink sink(out);
    a.trace_all(rays, sink);
    return out;
}

bool same_hit(const accel::Hit& a, const accel::Hit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) && a.prim == b.prim &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

bool same_point(const accel::PointHit& a, const accel::PointHit& b) {
    const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
    return bits(a.distance) == bits(b.distance) && a.prim == b.prim && bits(a.point.x) == bits(b.point.x) &&
           bits(a.point.y) == bits(b.point.y) && bits(a.point.z) == bits(b.point.z) && bits(a.u) == bits(b.u) &&
           bits(a.v) == bits(b.v);
}

}  // namespace arbor::testing
