// arbor_extreme_search: a directed search for rays on which a structure's closest hit differs from
// brute force's, where libFuzzer only stumbles on them: origins on (or within a few ulps of)
// surface points, directions of 2^emin..2^emax with a component that may be zero or ~1e-42, and,
// with --meshes, tiny meshes with coordinates anywhere in float range. Every structure and path
// against brute (the fuzz harnesses' contract, spec/rayfile.md rule), counted per structure and
// path; the first disagreements are printed as rays (hex floats) to replay. Exit 1 when any is
// found. docs/robustness.md, "Beyond CI: the directed search", lists what it has found.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "fuzz/fuzz_targets.h"
#include "stress/run.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

using namespace arbor;
using accel::Ray;
using accel::Vec3f;

namespace {

struct Options {
    std::uint32_t seed = 1;
    int iterations = 1000;
    int emin = 60, emax = 127;
    bool meshes = false;
    bool far = false;
    int show = 5;
};

/// A few triangles with coordinates of any magnitude (0, ~1, ~scale, powers of two, ~FLT_MAX).
engine::Mesh extreme_mesh(std::mt19937& rng, int triangles) {
    static const float scales[] = {1.0f, 1e10f, 1e20f, 1e30f, 1e37f, 3e38f};
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    float scale[3];
    for (float& s : scale) s = scales[std::uniform_int_distribution<int>(0, 5)(rng)];
    auto value = [&](int axis) {
        switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
            case 0: return 0.0f;
            case 1: return u(rng);
            case 2: return u(rng) * scale[axis];
            case 3: return u(rng) * scale[axis] * 1e-6f;
            case 4: return std::ldexp(u(rng), std::uniform_int_distribution<int>(-149, 127)(rng));
            default: return u(rng) * 3.4e38f;
        }
    };
    engine::Mesh m;
    for (int v = 0; v < 3 * triangles; ++v) {
        m.x.push_back(value(0)), m.y.push_back(value(1)), m.z.push_back(value(2));
        m.indices.push_back(std::uint32_t(v));
    }
    m.compute_bounds();
    return m;
}

/// Rays from surface points of `m` (vertices, edge points, face points; a quarter moved by up to
/// 2^-40..1 of a unit), directions of 2^emin..2^emax, some with a zero or a ~1e-42 component.
std::vector<Ray> surface_rays(const engine::Mesh& m, std::mt19937& rng, const Options& opt, std::size_t n) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t t = std::uniform_int_distribution<std::uint32_t>(0, std::uint32_t(m.triangle_count()) - 1)(rng);
        Vec3f p[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = m.indices[3 * std::size_t(t) + std::size_t(k)];
            p[k] = {m.x[v], m.y[v], m.z[v]};
        }
        const float a = unit(rng), b = std::uniform_real_distribution<float>(0.0f, 1.0f - a)(rng);
        const int mode = int(i % 4);
        Vec3f o = mode == 0 ? p[0] : mode == 1 ? p[0] * (1 - a) + p[1] * a : p[0] * (1 - a - b) + p[1] * a + p[2] * b;
        if (mode == 3) o = o + Vec3f{u(rng), u(rng), u(rng)} * std::ldexp(1.0f, std::uniform_int_distribution<int>(-40, 0)(rng));
        Vec3f d = Vec3f{u(rng), u(rng), u(rng)} * std::ldexp(1.0f, std::uniform_int_distribution<int>(opt.emin, opt.emax)(rng));
        if (i % 7 == 0) d.x = 0.0f;
        if (i % 11 == 0) d.y = std::ldexp(u(rng), -140);
        float tnear = i % 5 == 0 ? -INFINITY : 0.0f, tfar = INFINITY;
        if (opt.far) {
            // The origin moved back along the ray by 2^0..2^40 units (the surface point at t = s),
            // one coordinate made denormal, and the range around s or behind the origin.
            const float s = std::ldexp(unit(rng) + 0.5f, std::uniform_int_distribution<int>(0, 40)(rng));
            const float len = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
            o = o - d * (s / len);
            o[int(i % 3)] = std::ldexp(u(rng), -135);
            if (i % 2) tnear = -std::ldexp(1.0f, 30), tfar = 0.0f;
        }
        rays.push_back({o, tnear, d, tfar});
    }
    return rays;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    CLI::App app{"arbor_extreme_search: rays on which a structure's closest hit differs from brute force's"};
    app.add_option("--seed", opt.seed, "random seed");
    app.add_option("--iterations", opt.iterations, "batches of 256 rays")->check(CLI::Range(1, 1000000));
    app.add_option("--emin", opt.emin, "smallest direction exponent")->check(CLI::Range(-100, 127));
    app.add_option("--emax", opt.emax, "largest direction exponent")->check(CLI::Range(-100, 127));
    app.add_flag("--meshes", opt.meshes, "a new extreme mesh per batch instead of the fuzz harness's ray scene");
    app.add_flag("--far", opt.far, "origins moved back along the ray by 1..2^40 units, one coordinate denormal, some ranges behind the origin");
    app.add_option("--show", opt.show, "disagreements to print");
    CLI11_PARSE(app, argc, argv);
    if (opt.emin > opt.emax) {
        std::fprintf(stderr, "arbor_extreme_search: --emin %d is above --emax %d\n", opt.emin, opt.emax);
        return 2;
    }
    std::mt19937 rng(opt.seed);
    const engine::Mesh& scene = fuzz::ray_scene();
    std::map<std::string, std::size_t> differ;
    std::size_t rays_traced = 0, shown = 0;
    for (int it = 0; it < opt.iterations; ++it) {
        const engine::Mesh mesh = opt.meshes ? extreme_mesh(rng, 1 + it % 6) : engine::Mesh{};
        const engine::Mesh& m = opt.meshes ? mesh : scene;
        const std::vector<Ray> rays = surface_rays(m, rng, opt, 256);
        const accel::TriangleView view = m.view();
        const accel::BruteAccel brute(view);
        std::vector<accel::Hit> ref(rays.size()), got(rays.size());
        brute.trace(rays, ref, {accel::Query::closest, accel::TracePath::scalar});
        rays_traced += rays.size();
        for (accel::AccelKind kind : stress::buildable_kinds())
        for (const accel::KdWalk walk : {accel::KdWalk::tight_cells, accel::KdWalk::cells, accel::KdWalk::ropes}) {
            // (The kd-tree's SIMD paths of both walks, KdBlockConfig::walk; the others once.)
            if (kind == accel::AccelKind::brute || (kind != accel::AccelKind::kdtree && walk != accel::KdWalk::tight_cells)) continue;
            accel::BuildConfig cfg;
            cfg.kd_blocks.walk = walk;
            const auto a = accel::make_accel(kind, view, cfg);
            for (accel::TracePath path : stress::paths_of(*a)) {
                if (kind == accel::AccelKind::kdtree && walk != accel::KdWalk::tight_cells && path == accel::TracePath::scalar) continue;
                a->trace(rays, got, {accel::Query::closest, path});
                const std::string name = std::string(accel::to_string(kind)) +
                                         (kind == accel::AccelKind::kdtree && path != accel::TracePath::scalar
                                              ? "/" + std::string(accel::kd_walk_name(walk))
                                              : "") +
                                         "/" + std::string(accel::to_string(path));
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    if (accel::hits_agree(ref[i], got[i])) continue;
                    ++differ[name];
                    if (shown < std::size_t(opt.show)) {
                        ++shown;
                        const Ray& r = rays[i];
                        std::printf("%s: o=(%a %a %a) d=(%a %a %a) t=[%a, %a]: brute t=%a prim=%u, got t=%a prim=%u\n", name.c_str(),
                                    r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, ref[i].t, ref[i].prim,
                                    got[i].t, got[i].prim);
                    }
                }
            }
        }
    }
    std::size_t total = 0;
    for (const auto& [name, n] : differ) total += n;
    std::printf("%zu rays (%s%s, directions 2^%d..2^%d, seed %u): %zu disagreements with brute\n", rays_traced,
                opt.meshes ? "extreme meshes" : "the fuzz harness's ray scene", opt.far ? ", far origins" : "", opt.emin, opt.emax,
                opt.seed, total);
    for (const auto& [name, n] : differ) std::printf("  %-22s %zu\n", name.c_str(), n);
    return total == 0 ? 0 : 1;
}
