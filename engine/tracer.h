#pragma once
/// Tracer: the renderer's one door to the acceleration structure. Integrators hand it whole
/// batches of rays of one kind (a tile's camera rays, its shadow rays, its bounce rays); it tells
/// the structure how coherent the kind is (the path policy then takes packets for coherent kinds
/// and single-ray SIMD for incoherent ones, when the structure has them and they pay), and counts
/// rays and time per kind. One Tracer per thread.
#include "accel/interface/accel.h"
#include "accel/util/timer.h"
#include "engine/render_settings.h"

#include <span>

namespace arbor::engine {

/// What the renderer knows of a batch's rays: camera rays and shadow rays of a tile are coherent,
/// bounces are not. The path policy (accel/interface/path_policy.h) turns that into a path.
inline accel::RayHint ray_hint(RenderRayKind k) {
    return k == RenderRayKind::primary || k == RenderRayKind::shadow ? accel::RayHint::coherent : accel::RayHint::incoherent;
}

class Tracer {
public:
    explicit Tracer(const accel::Accel& a) : accel_(a) {}

    /// Closest hits of `rays` (all of kind k) into `hits`.
    void closest(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, RenderRayKind k) {
        if (rays.empty()) return;
        const accel::Timer t;
        accel_.trace(rays, hits, {accel::Query::closest, accel::TracePath::best, ray_hint(k)});
        add(k, rays.size(), t.seconds());
    }
    /// Any-hit (occlusion) queries of `rays` into `hits`.
    void any(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, RenderRayKind k) {
        if (rays.empty()) return;
        const accel::Timer t;
        accel_.trace(rays, hits, {accel::Query::any, accel::TracePath::best, ray_hint(k)});
        add(k, rays.size(), t.seconds());
    }

    /// The counted mode (accel/core/query.h, TraceRequest::counters): the closest hit of each ray
    /// on the structure's counting loop, and what that ray alone cost it in `per_ray`. Neither
    /// counted nor timed as a ray kind (the cost integrator times the same rays on the normal
    /// path). False when the structure cannot count (a BVH built without its scalar layout).
    bool counted(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, std::span<accel::TraceCounters> per_ray) {
        if (!accel_.offer().counts) return false;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            per_ray[i] = {};
            accel_.trace(rays.subspan(i, 1), hits.subspan(i, 1), {accel::Query::closest, accel::TracePath::scalar, {}, {}, &per_ray[i]});
        }
        return true;
    }

    std::array<std::uint64_t, render_ray_kind_count> counts{};  ///< rays traced per kind
    std::array<double, render_ray_kind_count> seconds{};       ///< time inside the structure per kind

private:
    void add(RenderRayKind k, std::size_t n, double s) {
        counts[std::size_t(k)] += n;
        seconds[std::size_t(k)] += s;
    }
    const accel::Accel& accel_;
};

}  // namespace arbor::engine
