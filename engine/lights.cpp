#include "engine/lights.h"

#include "accel/core/offset_ray.h"

#include "engine/sampling.h"

#include <algorithm>

namespace arbor::engine {

LightSet::LightSet(const Scene& scene) : points_(scene.lights) {
    const Mesh& m = scene.mesh;
    if (m.materials.empty()) return;
    const auto view = m.view();
    double total = 0.0;
    std::vector<double> power;
    // Instances' triangles are not sampled as lights (they glow where rays meet them): only the
    // triangles drawn as they are.
    const std::size_t lit = scene.placed.empty() ? m.triangle_count() : scene.placed.drawn;
    for (std::size_t t = 0; t < lit; ++t) {
        const Material& mat = m.materials[m.material.empty() ? 0 : m.material[t]];
        if (is_black(mat.emission) || !view.triangle_is_finite(t)) continue;
        Emitter e;
        e.prim = std::uint32_t(t);
        e.v0 = view.corner(t, 0);
        e.e1 = view.corner(t, 1) - e.v0;
        e.e2 = view.corner(t, 2) - e.v0;
        const Vec3f n = simd::cross(e.e1, e.e2);
        const float len = simd::length(n);
        if (!(len > 0.0f) || !std::isfinite(len)) continue;
        e.normal = n / len;
        e.area = 0.5f * len;
        e.scale = accel::triangle_scale(view.corner(t, 0), view.corner(t, 1), view.corner(t, 2));
        e.radiance = mat.emission;
        const double p = double(e.area) * std::max(1e-6f, luminance(mat.emission));
        emitters_.push_back(e);
        power.push_back(p);
        total += p;
    }
    if (emitters_.empty()) return;
    cdf_.resize(emitters_.size());
    pick_.resize(emitters_.size());
    double acc = 0.0;
    for (std::size_t i = 0; i < emitters_.size(); ++i) {
        acc += power[i];
        cdf_[i] = float(acc / total);
        pick_[i] = float(power[i] / total);
    }
    cdf_.back() = 1.0f;
}

AreaSample LightSet::sample_area(float u_pick, float u1, float u2) const {
    // First emitter whose cdf exceeds u_pick; u_pick < 1 and cdf_.back() == 1 keep it in range.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u_pick);
    const std::size_t i = std::min(std::size_t(it - cdf_.begin()), cdf_.size() - 1);
    const Emitter& e = emitters_[i];
    float b1, b2;
    uniform_triangle(u1, u2, b1, b2);
    AreaSample s;
    s.point = e.v0 + e.e1 * b1 + e.e2 * b2;
    s.normal = e.normal;
    s.scale = e.scale;
    s.radiance = e.radiance;
    s.pdf_area = pick_[i] / e.area;
    return s;
}

}  // namespace arbor::engine
