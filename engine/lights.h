#pragma once
/// The lights a renderer can sample: the scene's point lights and every emissive triangle of its
/// mesh (an area light, emitting Ke from both sides). Built once per render, read-only after.
#include "engine/scene.h"

#include <cstdint>
#include <vector>

namespace arbor::engine {

/// A point on an area light, drawn by LightSet::sample_area.
struct AreaSample {
    Vec3f point;       ///< on the triangle
    Vec3f normal;      ///< unit geometric normal of the triangle (either side emits)
    float scale = 0.0f;  ///< accel::triangle_scale of the triangle (for offset_ray_origin)
    Vec3f radiance;    ///< Ke of the triangle
    float pdf_area = 0.0f;  ///< density per unit area over all emitters (selection x 1/area)
};

class LightSet {
public:
    /// Collects the point lights and the emissive triangles (Ke > 0, area > 0, finite) of `scene`.
    /// Triangles are picked in proportion to power (area x luminance of Ke).
    explicit LightSet(const Scene& scene);

    const std::vector<PointLight>& points() const { return points_; }
    std::size_t emitter_count() const { return emitters_.size(); }
    bool has_area() const { return !emitters_.empty(); }
    bool empty() const { return points_.empty() && emitters_.empty(); }

    /// A point on one emitter from three uniform numbers. Requires has_area().
    AreaSample sample_area(float u_pick, float u1, float u2) const;

private:
    struct Emitter {
        std::uint32_t prim;
        Vec3f v0, e1, e2, normal, radiance;
        float area;
        float scale;  // accel::triangle_scale of the corners, for AreaSample::scale
    };
    std::vector<PointLight> points_;
    std::vector<Emitter> emitters_;
    std::vector<float> cdf_;  // cdf_[i] = power of emitters 0..i / total; the last is exactly 1
    std::vector<float> pick_;  // selection probability of each emitter
};

}  // namespace arbor::engine
