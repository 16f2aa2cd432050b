#pragma once
/// `brute`: tests every triangle with the scalar watertight test. The oracle for every other path.
#include "accel/accel.h"

#include <vector>

namespace arbor::accel {

class BruteAccel final : public Accel {
public:
    /// Copies the corners of every finite triangle (non-finite ones are dropped and counted).
    explicit BruteAccel(const TriangleView& tris);

    /// One ray, the plain loop: closest hit or the first hit found.
    Hit trace_one(const Ray& ray, Query query) const;

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

}  // namespace arbor::accel
