#include "stress/oracle.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace arbor::stress {

namespace {

constexpr double unit_roundoff = 0x1p-24;  // float
constexpr double err_k = 16.0;             // see the error model in oracle.h
constexpr double inf = std::numeric_limits<double>::infinity();
/// Float products beyond this may overflow, below it they lose their sign to underflow.
constexpr double float_big = 1e37, float_small = 1e-30;

/// The ray in double, with the watertight test's frame: kz is the dominant axis (ties as
/// simd::max_axis), kx/ky the other two, s the shear.
struct Frame {
    double o[3], d[3];
    int kx, ky, kz;
    double sx, sy, sz;
    double tnear, tfar, dlen2;
};

Frame make_frame(const Ray& r) {
    Frame f;
    for (int k = 0; k < 3; ++k) f.o[k] = r.org[k], f.d[k] = r.dir[k];
    const double ax = std::fabs(f.d[0]), ay = std::fabs(f.d[1]), az = std::fabs(f.d[2]);
    f.kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    f.kx = (f.kz + 1) % 3;
    f.ky = (f.kx + 1) % 3;
    if (std::signbit(f.d[f.kz])) std::swap(f.kx, f.ky);
    f.sx = f.d[f.kx] / f.d[f.kz];
    f.sy = f.d[f.ky] / f.d[f.kz];
    f.sz = 1.0 / f.d[f.kz];
    f.tnear = r.tnear, f.tfar = r.tfar;
    f.dlen2 = f.d[0] * f.d[0] + f.d[1] * f.d[1] + f.d[2] * f.d[2];
    return f;
}

bool is_float(double x) { return double(float(x)) == x; }

/// -1, 0, +1 when the sign of an edge function is certain, 2 when its error bound covers 0.
int sign_class(double e, double bound) {
    if (e > bound) return 1;
    if (e < -bound) return -1;
    if (bound == 0.0 && e == 0.0) return 0;
    return 2;
}

TriVerdict classify_tri(const Frame& f, const Vec3f (&v)[3]) {
    double a[3][3], scale = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            a[i][k] = double(v[i][k]) - f.o[k];
            scale = std::max(scale, std::fabs(a[i][k]));
        }
    // A coordinate with zero shear is v[k] - o[k] itself: exact when that difference is a float.
    bool exact_x = f.sx == 0.0, exact_y = f.sy == 0.0;
    for (int i = 0; i < 3; ++i) exact_x = exact_x && is_float(a[i][f.kx]), exact_y = exact_y && is_float(a[i][f.ky]);
    const double dx = exact_x ? 0.0 : err_k * unit_roundoff * scale;
    const double dy = exact_y ? 0.0 : err_k * unit_roundoff * scale;
    double px[3], py[3], pz[3];
    for (int i = 0; i < 3; ++i) {
        px[i] = a[i][f.kx] - f.sx * a[i][f.kz];
        py[i] = a[i][f.ky] - f.sy * a[i][f.kz];
        pz[i] = a[i][f.kz];
    }
    const double U = px[2] * py[1] - py[2] * px[1];
    const double V = px[0] * py[2] - py[0] * px[2];
    const double W = px[1] * py[0] - py[1] * px[0];
    // Error bounds: coordinates off by dx, dy; plus double rounding when anything is inexact.
    const double r = exact_x && exact_y ? 0.0 : 0x1p-50;
    const double eU = dx * (std::fabs(py[1]) + std::fabs(py[2])) + dy * (std::fabs(px[2]) + std::fabs(px[1])) + 2 * dx * dy +
                      r * (std::fabs(px[2] * py[1]) + std::fabs(py[2] * px[1]));
    const double eV = dx * (std::fabs(py[2]) + std::fabs(py[0])) + dy * (std::fabs(px[0]) + std::fabs(px[2])) + 2 * dx * dy +
                      r * (std::fabs(px[0] * py[2]) + std::fabs(py[0] * px[2]));
    const double eW = dx * (std::fabs(py[0]) + std::fabs(py[1])) + dy * (std::fabs(px[1]) + std::fabs(px[0])) + 2 * dx * dy +
                      r * (std::fabs(px[1] * py[0]) + std::fabs(py[1] * px[0]));
    int s[3] = {sign_class(U, eU), sign_class(V, eV), sign_class(W, eW)};
    // An exactly zero edge function: the ray passes exactly through the edge p -> q. On exact
    // coordinates (the float test's own) it takes the sign the triangle test's tie rule gives it:
    // that of F(x, y) = (qx - x)(py - y) - (qy - y)(px - x) at the point (e, e*h), e and h
    // infinitesimal: of dF/dx = qy - py, else of dF/dy = px - qx. Otherwise it is unsure.
    const int from[3] = {1, 2, 0}, to[3] = {2, 0, 1};  // U: edge b -> c, V: c -> a, W: a -> b
    for (int k = 0; k < 3; ++k) {
        if (s[k] != 0) continue;
        if (!(exact_x && exact_y)) {
            s[k] = 2;
            continue;
        }
        const double fx = py[to[k]] - py[from[k]], fy = px[from[k]] - px[to[k]];
        s[k] = fx != 0.0 ? (fx > 0.0 ? 1 : -1) : fy != 0.0 ? (fy > 0.0 ? 1 : -1) : 0;
    }
    bool pos = false, neg = false, unsure = false;
    for (int c : s) pos |= c == 1, neg |= c == -1, unsure |= c == 2;
    TriVerdict out;
    if (pos && neg) return out;  // certainly outside an edge
    const double det = U + V + W, edet = eU + eV + eW;
    if (!unsure && det == 0.0) return out;  // degenerate triangle or seen edge-on, exactly
    // Beyond float range the float test overflows or loses signs: it cannot be judged.
    double pmax = 0.0;
    for (int i = 0; i < 3; ++i) pmax = std::max({pmax, std::fabs(px[i]), std::fabs(py[i]), std::fabs(pz[i])});
    const double emax = std::max({std::fabs(U), std::fabs(V), std::fabs(W)});
    const bool out_of_range = pmax * pmax > float_big || (emax < float_small && emax > 0.0);
    if (std::fabs(det) <= edet) {  // seen (nearly) edge-on: t is unknown
        out.kind = TriVerdict::unsure;
        out.t = 0.0;
        out.tol = inf;
        return out;
    }
    const double t = (U * pz[0] + V * pz[1] + W * pz[2]) / det * f.sz;
    const double zmax = std::max({std::fabs(pz[0]), std::fabs(pz[1]), std::fabs(pz[2])}) * std::fabs(f.sz);
    const double wsum = (std::fabs(U) + std::fabs(V) + std::fabs(W)) / std::fabs(det);
    const double tol = (err_k * unit_roundoff + (1.0 + wsum) * edet / std::fabs(det)) * zmax + err_k * unit_roundoff * std::fabs(t);
    if (t + tol < f.tnear || t - tol > f.tfar) return out;  // certainly outside [tnear, tfar]
    out.t = t;
    out.tol = tol;
    const bool inside = t - tol >= f.tnear && t + tol <= f.tfar && std::fabs(t) < 1e38;
    out.kind = unsure || !inside || out_of_range ? TriVerdict::unsure : TriVerdict::hit;
    return out;
}

}  // namespace

Oracle::Oracle(const accel::TriangleView& tris) : slot_(tris.triangle_count(), -1) {
    for (std::size_t i = 0; i < tris.triangle_count(); ++i) {
        if (!tris.triangle_is_finite(i)) continue;
        Tri t;
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            t.v[k] = tris.corner(i, k);
            for (int j = 0; j < 3; ++j) c[j] += double(t.v[k][j]) / 3.0;
        }
        double r2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            double d2 = 0.0;
            for (int j = 0; j < 3; ++j) d2 += (double(t.v[k][j]) - c[j]) * (double(t.v[k][j]) - c[j]);
            r2 = std::max(r2, d2);
        }
        t.cx = c[0], t.cy = c[1], t.cz = c[2], t.radius = std::sqrt(r2);
        slot_[i] = std::int64_t(tris_.size());
        tris_.push_back(t);
        prims_.push_back(std::uint32_t(i));
    }
}

TriVerdict Oracle::classify(const Ray& ray, std::uint32_t prim) const {
    if (!accel::ray_is_traceable(ray) || prim >= slot_.size() || slot_[prim] < 0) return {};
    return classify_tri(make_frame(ray), tris_[std::size_t(slot_[prim])].v);
}

OracleAnswer Oracle::answer(const Ray& ray) const {
    OracleAnswer out;
    out.t_hit = inf;
    out.traceable = accel::ray_is_traceable(ray);
    if (!out.traceable) return out;
    const Frame f = make_frame(ray);
    const double dlen = std::sqrt(f.dlen2);
    bool any_unsure = false;
    double unsure_first = inf;  // smallest t - tol over unsure triangles
    for (std::size_t i = 0; i < tris_.size(); ++i) {
        const Tri& tri = tris_[i];
        // Cull triangles whose bounding sphere is far from the ray's line, with a margin far
        // above any float error the test below could call a hit.
        const double wx = tri.cx - f.o[0], wy = tri.cy - f.o[1], wz = tri.cz - f.o[2];
        const double cx = wy * f.d[2] - wz * f.d[1], cy = wz * f.d[0] - wx * f.d[2], cz = wx * f.d[1] - wy * f.d[0];
        const double dist = std::sqrt(cx * cx + cy * cy + cz * cz) / dlen;
        const double w = std::fabs(wx) + std::fabs(wy) + std::fabs(wz);
        if (dist > tri.radius + 1e-5 * (w + tri.radius)) continue;
        const TriVerdict v = classify_tri(f, tri.v);
        if (v.kind == TriVerdict::hit) {
            if (v.t < out.t_hit) out.t_hit = v.t, out.t_hit_tol = v.tol, out.prim = prims_[i];
        } else if (v.kind == TriVerdict::unsure) {
            any_unsure = true;
            unsure_first = std::min(unsure_first, v.t - v.tol);
        }
    }
    out.band = any_unsure && unsure_first <= out.t_hit + out.t_hit_tol;
    return out;
}

int Oracle::crossings(const Ray& ray) const {
    if (!accel::ray_is_traceable(ray)) return 0;
    const Frame f = make_frame(ray);
    int n = 0;
    for (const Tri& tri : tris_) {
        const TriVerdict v = classify_tri(f, tri.v);
        if (v.kind == TriVerdict::unsure) return -1;
        n += v.kind == TriVerdict::hit;
    }
    return n;
}

std::vector<OracleAnswer> Oracle::answers(std::span<const Ray> rays) const {
    std::vector<OracleAnswer> out(rays.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = answer(rays[i]);
    });
    return out;
}

}  // namespace arbor::stress
