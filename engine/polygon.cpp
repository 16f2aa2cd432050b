#include "engine/polygon.h"

#include <cmath>

namespace arbor::engine {

namespace {

/// The polygon's corners in 2D, oriented so that its winding is counter-clockwise: the two axes
/// the Newell normal is least along, the normal's dominant axis dropped. Empty when the Newell
/// normal is zero or not finite.
std::vector<std::array<double, 2>> project(std::span<const Vec3f> c) {
    double n[3] = {0, 0, 0};  // Newell's normal, in double so that nearly flat polygons keep their sign
    const std::size_t k = c.size();
    for (std::size_t i = 0; i < k; ++i) {
        const Vec3f& a = c[i];
        const Vec3f& b = c[(i + 1) % k];
        n[0] += (double(a.y) - b.y) * (double(a.z) + b.z);
        n[1] += (double(a.z) - b.z) * (double(a.x) + b.x);
        n[2] += (double(a.x) - b.x) * (double(a.y) + b.y);
    }
    int axis = 0;
    for (int d = 1; d < 3; ++d)
        if (std::fabs(n[d]) > std::fabs(n[axis])) axis = d;
    if (!(std::fabs(n[axis]) > 0.0) || !std::isfinite(n[axis])) return {};
    // Dropping `axis` leaves (u, w) = the next two axes in cyclic order: counter-clockwise when n[axis] > 0.
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    const double flip = n[axis] > 0 ? 1.0 : -1.0;
    std::vector<std::array<double, 2>> p(k);
    for (std::size_t i = 0; i < k; ++i) p[i] = {double(c[i][u]), flip * double(c[i][w])};
    return p;
}

double cross(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

bool convex_2d(const std::vector<std::array<double, 2>>& p) {
    const std::size_t k = p.size();
    int x_turns = 0;
    double last_dx = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
        if (cross(p[(i + k - 1) % k], p[i], p[(i + 1) % k]) < 0.0) return false;
        // A star polygon turns one way too but winds more than once: its edges' x direction changes
        // sign more than twice around the loop.
        const double dx = p[(i + 1) % k][0] - p[i][0];
        if (dx != 0.0) {
            if (last_dx != 0.0 && (dx > 0) != (last_dx > 0)) ++x_turns;
            last_dx = dx;
        }
    }
    // Close the loop: compare the last non-zero direction with the first.
    for (std::size_t i = 0; i < k; ++i) {
        const double dx = p[(i + 1) % k][0] - p[i][0];
        if (dx != 0.0) {
            if (last_dx != 0.0 && (dx > 0) != (last_dx > 0)) ++x_turns;
            break;
        }
    }
    return x_turns <= 2;
}

/// True when q is inside or on triangle (a, b, c), which is counter-clockwise.
bool in_triangle(const std::array<double, 2>& q, const std::array<double, 2>& a, const std::array<double, 2>& b,
                 const std::array<double, 2>& c) {
    return cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0;
}

void ear_clip(const std::vector<std::array<double, 2>>& p, std::vector<std::array<std::uint32_t, 3>>& out) {
    const std::size_t k = p.size();
    std::vector<std::uint32_t> prev(k), next(k);
    for (std::size_t i = 0; i < k; ++i) {
        prev[i] = std::uint32_t((i + k - 1) % k);
        next[i] = std::uint32_t((i + 1) % k);
    }
    auto same = [&](std::uint32_t a, std::uint32_t b) { return p[a][0] == p[b][0] && p[a][1] == p[b][1]; };
    auto is_ear = [&](std::uint32_t i) {
        const std::uint32_t a = prev[i], c = next[i];
        if (!(cross(p[a], p[i], p[c]) > 0.0)) return false;  // reflex or flat corner
        // No other remaining corner may lie in the ear (corners at the ear's own positions, as the
        // two ends of a bridge into a hole, do not count).
        for (std::uint32_t j = next[c]; j != a; j = next[j])
            if (!same(j, a) && !same(j, i) && !same(j, c) && in_triangle(p[j], p[a], p[i], p[c])) return false;
        return true;
    };
    std::size_t left = k;
    std::uint32_t i = 0;
    std::size_t misses = 0;  // corners tried since the last ear
    while (left > 3) {
        if (is_ear(i) || misses >= left) {
            // misses >= left: no ear in a whole round (a self-intersecting or degenerate polygon);
            // cut the corner anyway so that the polygon still gives its k - 2 triangles.
            out.push_back({prev[i], i, next[i]});
            next[prev[i]] = next[i];
            prev[next[i]] = prev[i];
            i = prev[i];  // the neighbours' ear status changed; start the search there
            --left;
            misses = 0;
        } else {
            i = next[i];
            ++misses;
        }
    }
    out.push_back({prev[i], i, next[i]});
}

}  // namespace

bool polygon_is_convex(std::span<const Vec3f> corners) {
    if (corners.size() <= 3) return true;
    const auto p = project(corners);
    return p.empty() || convex_2d(p);
}

void triangulate_polygon(std::span<const Vec3f> corners, std::vector<std::array<std::uint32_t, 3>>& out) {
    const std::size_t k = corners.size();
    if (k < 3) return;
    if (k > 3) {
        const auto p = project(corners);
        if (!p.empty() && !convex_2d(p)) return ear_clip(p, out);
    }
    for (std::size_t j = 1; j + 1 < k; ++j) out.push_back({0u, std::uint32_t(j), std::uint32_t(j + 1)});
}

}  // namespace arbor::engine
