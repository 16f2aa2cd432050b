// Ray input: NaN/Inf/zero-length/inactive rays (misses, found in O(1)), and valid but extreme
// rays (tnear = -inf, directions of length 1e-30 and 1e30, empty ranges on a surface).
#include "engine/procedural.h"
#include "stress/stress_case.h"

#include <random>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

engine::Mesh target_mesh(bool full) {
    engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, full ? 4 : 2, 0.1f, 6);
    m.append(engine::make_box({-3, -3, -3}, {3, -2.5f, 3}));
    m.compute_bounds();
    return m;
}

}  // namespace

void add_ray_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    std::mt19937 rng(71);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    auto random_ray = [&] {
        const Vec3f d{normal(rng), normal(rng), normal(rng)};
        return accel::Ray{Vec3f{0.1f, 0.2f, 0.05f} - d * 4.0f, 0.0f, d, inf};
    };
    {
        StressCase c;
        c.name = "nonfinite-rays";
        c.what = "NaN/Inf in origin, direction, tnear, tfar; zero and all-denormal directions; tfar < tnear: all miss, in O(1)";
        c.mesh = target_mesh(full);
        const float bad_values[] = {nan, -nan, inf, -inf};
        const std::size_t rounds = full ? 200 : 20;
        for (std::size_t round = 0; round < rounds; ++round) {
            // Every ray would hit without its defect: it points at the sphere.
            for (float bad : bad_values)
                for (int field = 0; field < 8; ++field) {
                    accel::Ray r = random_ray();
                    if (field < 3) r.org[field] = bad;
                    else if (field < 6) r.dir[field - 3] = bad;
                    else if (field == 6) r.tnear = std::isnan(bad) ? bad : nan;  // tnear = -inf is valid
                    else if (std::isnan(bad) || bad < 0.0f) r.tfar = bad;  // NaN, or -inf < tnear
                    else r.tnear = bad, r.tfar = 1e30f;                   // tnear = +inf > tfar
                    c.add(r);
                }
            accel::Ray zero = random_ray();
            zero.dir = {round % 2 ? -0.0f : 0.0f, round % 3 ? -0.0f : 0.0f, round % 5 ? 0.0f : -0.0f};
            c.add(zero);
            // All components denormal: zero-length by the rule (1/d overflows on every axis).
            accel::Ray tiny = random_ray();
            tiny.dir = {round % 2 ? 1e-39f : -3e-42f, 5e-40f, round % 3 ? -1.1e-38f : 0.0f};
            c.add(tiny);
            accel::Ray inactive = random_ray();
            inactive.tnear = 2.0f, inactive.tfar = 1.0f;
            c.add(inactive);
        }
        out.push_back(std::move(c));
    }
    {
        StressCase c;
        c.name = "extreme-rays";
        c.what = "valid but extreme rays: tnear = -inf, |d| = 1e-30 and 1e30, denormal components, tnear = tfar, origins on the surface";
        c.mesh = target_mesh(full);
        const std::size_t rounds = full ? 500 : 50;
        for (std::size_t round = 0; round < rounds; ++round) {
            accel::Ray r = random_ray();
            accel::Ray a = r;
            a.tnear = -inf;  // hits behind the origin count too
            c.add(a);
            accel::Ray tiny = r;
            tiny.dir = r.dir * 1e-30f;
            c.add(tiny);
            accel::Ray huge = r;
            huge.dir = r.dir * 1e30f;
            c.add(huge);
            accel::Ray near_axis = r;  // one normal component, the others denormal: valid
            near_axis.dir = {r.dir.x, 1e-40f, -2e-39f};
            c.add(near_axis);
            accel::Ray point = r;
            point.tnear = point.tfar = 4.0f;  // a range of one point (inside the sphere: no surface there)
            c.add(point);
            // From a vertex of the sphere outwards and inwards: t = 0 is on the surface.
            const std::uint32_t v = std::uint32_t(round * 7 % c.mesh.vertex_count());
            const Vec3f p{c.mesh.x[v], c.mesh.y[v], c.mesh.z[v]};
            c.add({p, 0.0f, p, inf});
            c.add({p, 0.0f, -p, inf});
        }
        out.push_back(std::move(c));
    }
}

std::vector<StressCase> make_stress_cases(Size size) {
    std::vector<StressCase> out;
    add_closed_cases(out, size);
    add_grid_cases(out, size);
    add_precision_cases(out, size);
    add_degenerate_cases(out, size);
    add_in_plane_cases(out, size);
    add_ray_cases(out, size);
    return out;
}

}  // namespace arbor::stress
