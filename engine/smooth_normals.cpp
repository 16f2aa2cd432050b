#include "engine/smooth_normals.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace arbor::engine {

namespace {

/// Position classes: class[v] is the smallest vertex index with bit-equal coordinates.
std::vector<std::uint32_t> weld(const Mesh& m) {
    std::vector<std::uint32_t> order(m.vertex_count());
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](std::uint32_t v) { return std::tuple(m.x[v], m.y[v], m.z[v]); };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
    std::vector<std::uint32_t> cls(m.vertex_count());
    for (std::size_t i = 0; i < order.size(); ++i)
        cls[order[i]] = i > 0 && key(order[i]) == key(order[i - 1]) ? cls[order[i - 1]] : order[i];
    return cls;
}

float corner_angle(const Vec3f& p, const Vec3f& a, const Vec3f& b) {
    const Vec3f e1 = a - p, e2 = b - p;
    const float l = simd::length(e1) * simd::length(e2);
    if (!(l > 0.0f)) return 0.0f;
    return std::acos(std::clamp(simd::dot(e1, e2) / l, -1.0f, 1.0f));
}

}  // namespace

std::size_t compute_smooth_normals(Mesh& m, float crease_degrees) {
    const std::size_t tris = m.triangle_count();
    if (tris == 0) return 0;
    if (m.normal_index.empty()) m.normal_index.assign(3 * tris, no_attribute);
    const auto view = m.view();
    std::vector<Vec3f> face(tris);
    std::vector<float> angle(3 * tris);
    for (std::size_t t = 0; t < tris; ++t) {
        const Vec3f a = view.corner(t, 0), b = view.corner(t, 1), c = view.corner(t, 2);
        const Vec3f n = simd::cross(b - a, c - a);
        const float len = simd::length(n);
        face[t] = len > 0.0f && std::isfinite(len) ? n / len : Vec3f{0.0f};
        angle[3 * t] = corner_angle(a, b, c);
        angle[3 * t + 1] = corner_angle(b, c, a);
        angle[3 * t + 2] = corner_angle(c, a, b);
    }
    // Corners around each position class, compressed rows (CSR).
    const std::vector<std::uint32_t> cls = weld(m);
    std::vector<std::uint32_t> start(m.vertex_count() + 1, 0);
    for (std::uint32_t v : m.indices) ++start[cls[v] + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::uint32_t> corners(m.indices.size()), fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < m.indices.size(); ++k) corners[fill[cls[m.indices[k]]]++] = std::uint32_t(k);

    const float cos_crease = std::cos(crease_degrees * std::numbers::pi_v<float> / 180.0f);
    // One shared normal per class for corners whose every neighbour is within the crease.
    std::vector<std::uint32_t> shared(m.vertex_count(), no_attribute);
    std::size_t filled = 0;
    for (std::size_t k = 0; k < m.indices.size(); ++k) {
        if (m.normal_index[k] != no_attribute) continue;
        const std::size_t t = k / 3;
        if (!(simd::dot(face[t], face[t]) > 0.0f)) continue;  // degenerate: stays flat
        const std::uint32_t c = cls[m.indices[k]];
        Vec3f sum{0.0f};
        bool all = true;
        for (std::uint32_t i = start[c]; i < start[c + 1]; ++i) {
            const std::size_t other = corners[i] / 3;
            if (simd::dot(face[other], face[t]) >= cos_crease) sum = sum + face[other] * angle[corners[i]];
            else if (simd::dot(face[other], face[other]) > 0.0f) all = false;
        }
        const float len = simd::length(sum);
        if (!(len > 0.0f) || !std::isfinite(len)) continue;
        if (all && shared[c] != no_attribute) {
            m.normal_index[k] = shared[c];
        } else {
            m.normals.push_back(sum / len);
            m.normal_index[k] = std::uint32_t(m.normals.size() - 1);
            if (all) shared[c] = m.normal_index[k];
        }
        ++filled;
    }
    if (filled == 0 && m.normals.empty()) m.normal_index.clear();
    return filled;
}

}  // namespace arbor::engine
