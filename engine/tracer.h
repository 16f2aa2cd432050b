#pragma once
/// Tracer: the renderer's one door to the acceleration structure. Integrators hand it whole
/// batches of rays of one kind (a tile's camera rays, its shadow rays, its bounce rays); it picks
/// the trace path for the kind (packets for coherent kinds, single-ray SIMD for incoherent ones,
/// when the structure has them), and counts rays and time per kind. One Tracer per thread.
#include "accel/accel.h"
#include "accel/util/timer.h"
#include "engine/render_settings.h"

#include <span>

namespace arbor::engine {

/// Coherent kinds (camera rays, shadow rays of a tile) go to packets; the others to single rays.
inline bool is_coherent(RenderRayKind k) { return k == RenderRayKind::primary || k == RenderRayKind::shadow; }

/// The trace path for rays of kind `k` on `accel`: packet or single when the structure has its
/// own implementation, otherwise `best`.
inline accel::TracePath trace_path_for(const accel::Accel& a, RenderRayKind k) {
    const accel::TracePath want = is_coherent(k) ? accel::TracePath::packet : accel::TracePath::single;
    return a.has_path(want) ? want : accel::TracePath::best;
}

class Tracer {
public:
    explicit Tracer(const accel::Accel& a) : accel_(a) {}

    /// Closest hits of `rays` (all of kind k) into `hits`.
    void closest(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, RenderRayKind k) {
        if (rays.empty()) return;
        const accel::Timer t;
        accel_.intersect(rays, hits, trace_path_for(accel_, k));
        add(k, rays.size(), t.seconds());
    }
    /// Any-hit (occlusion) queries of `rays` into `hits`.
    void any(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, RenderRayKind k) {
        if (rays.empty()) return;
        const accel::Timer t;
        accel_.occluded(rays, hits, trace_path_for(accel_, k));
        add(k, rays.size(), t.seconds());
    }

    /// Statistics mode (accel.h, TraceCounters): the closest hit of each ray on the structure's
    /// counting loop, and what that ray alone cost it in `per_ray`. Neither counted nor timed as a
    /// ray kind (the cost integrator times the same rays on the normal path). False when the
    /// structure cannot count (a BVH built without its scalar layout).
    bool counted(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, std::span<accel::TraceCounters> per_ray) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            per_ray[i] = {};
            if (!accel_.trace_counted(rays.subspan(i, 1), hits.subspan(i, 1), false, per_ray[i])) return false;
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
