#pragma once
/// `brute`: tests every triangle with the scalar watertight test. The oracle for every other path.
#include "accel/interface/accel.h"

#include <vector>

namespace arbor::accel {

class BruteAccel final : public Accel {
public:
    /// Copies the corners of every finite triangle (non-finite ones are dropped and counted).
    explicit BruteAccel(const TriangleView& tris);

    /// One ray, the plain loop: closest hit or the first hit found.
    Hit trace_one(const Ray& ray, Query query) const;
    /// Every triangle tested, every hit kept.
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    /// Every triangle's exact distance.
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;
    /// The exact sum over `tris` (make_exact_winding): brute force is the oracle.
    std::unique_ptr<WindingTree> make_winding_tree(const TriangleView& tris) const override;
    /// Copies the corners again (no tree, so nothing to lose: a refit is a rebuild here).
    std::string_view refit_unsupported() const override { return {}; }
    RefitResult refit(const TriangleView& tris) override;

private:
    /// One path (scalar), and the counted mode: one node (the whole list) per traceable ray, every
    /// triangle tested until the answer.
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override;
    template <bool AnyHit, bool Count> Hit trace_impl(const Ray& ray, TraceCounters* counters) const;

    struct Tri {
        Vec3f v0, v1, v2;
        std::uint32_t prim;
    };
    std::vector<Tri> tris_;
};

/// What a brute build offers: the scalar path and the counted mode.
PathOffer brute_offer();

}  // namespace arbor::accel
