#include "accel/core/solid_angle.h"
#include "accel/core/winding_tree.h"

#include <limits>

namespace arbor::accel {

namespace {

/// The plain sum: every finite triangle, in triangle order (the oracle of the hierarchical trees).
class ExactWinding final : public WindingTree {
public:
    explicit ExactWinding(const TriangleView& tris) : tris_(tris) {}
    void winding_numbers(std::span<const Vec3f> points, double, std::span<double> out,
                         std::span<double> bound) const override {
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Vec3f& p = points[i];
            double sum = std::numeric_limits<double>::quiet_NaN();
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
                sum = 0.0;
                for (std::size_t t = 0; t < tris_.triangle_count(); ++t)
                    if (tris_.triangle_is_finite(t))
                        sum += triangle_winding(p, tris_.corner(t, 0), tris_.corner(t, 1), tris_.corner(t, 2));
            }
            out[i] = sum;
            if (!bound.empty()) bound[i] = std::isnan(sum) ? sum : 0.0;
        }
    }
    std::string_view method() const override { return "exact"; }
    std::size_t memory_bytes() const override { return 0; }

private:
    TriangleView tris_;
};

}  // namespace

std::unique_ptr<WindingTree> make_exact_winding(const TriangleView& tris) {
    return std::make_unique<ExactWinding>(tris);
}

}  // namespace arbor::accel
