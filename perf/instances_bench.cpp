// `arbor-bench instances`: a mesh placed many times as instances (one bottom structure, a top BVH
// over the copies) against the same scene flattened (every copy's triangles in one structure), on
// the same rays. A benchmark, not a test: the answers are compared first (rays whose hit differs,
// by the rayfile.md rule or by triangle), then build and trace are timed. Usage:
//   arbor-bench instances [--model OBJ] [--copies N] [--accel NAME] [--rays N] [--repeat K] [--threads T]
//                         [--save-hits FILE]
// --save-hits writes the instanced scene's raw hit records (closest and any hit, on the scalar,
// single and packet paths, in that order) to FILE, so that two builds can be compared bit for bit.
// Copies sit on a square grid, each turned about a random axis and scaled (every third one
// mirrored, every fourth non-uniformly scaled). Rays: a camera grid over the scene and random rays
// inside its box (N of each). Times are medians of K runs, instanced and flattened interleaved.
// With the Embree peer built in (perf/embree_peer.h), Embree's instanced scene (its instances of
// one mesh scene, RTC_GEOMETRY_TYPE_INSTANCE) and its flattened scene are built and traced beside
// them, interleaved the same way, with Embree's fastest call on the instanced scene.
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "accel/factory/make_accel.h"
#include "accel/instances/instance_accel.h"
#include "accel/interface/trace.h"
#include "accel/util/timer.h"
#include "engine/mesh_loader.h"
#include "perf/commands.h"
#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

using namespace arbor;
using accel::Vec3f;

namespace {

struct Options {
    std::string model = ARBOR_SHARED_SCENES "/models/stanford-bunny.obj";
    std::string accel = "bvh-sah";
    int copies = 64, repeat = 5, threads = 2;
    std::size_t rays = 1u << 18;
    std::string save_hits;  ///< where to write the instanced scene's answers (for comparing builds)
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Copy c's transform: a turn about a random axis, a random scale (mirrored / non-uniform for some),
/// moved to its cell of the grid.
std::vector<accel::Affine> placements(const accel::Bounds& b, int copies) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int side = int(std::ceil(std::sqrt(double(copies))));
    const Vec3f e = b.extent(), c = b.center();
    const double size = std::max({e.x, e.y, e.z}), spacing = 1.3 * size;
    std::vector<accel::Affine> out;
    for (int k = 0; k < copies; ++k) {
        double ax[3] = {u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
        const double n = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
        for (double& a : ax) a /= n;
        const double ang = 6.283185307179586 * u(rng), co = std::cos(ang), si = std::sin(ang), C = 1 - co;
        const double x = ax[0], y = ax[1], z = ax[2];
        const double r[3][3] = {{co + x * x * C, x * y * C - z * si, x * z * C + y * si},
                                {y * x * C + z * si, co + y * y * C, y * z * C - x * si},
                                {z * x * C - y * si, z * y * C + x * si, co + z * z * C}};
        const double s = 0.6 + 0.4 * u(rng);
        double sc[3] = {s, s, s};
        if (k % 3 == 1) sc[0] = -s;                        // mirrored
        if (k % 4 == 2) sc[1] = s * 0.5, sc[2] = s * 1.2;  // non-uniform
        const double move[3] = {(k % side) * spacing, 0.0, (k / side) * spacing};
        accel::Affine a;
        for (int i = 0; i < 3; ++i) {
            double t = move[i];
            for (int j = 0; j < 3; ++j) {
                a.m[std::size_t(4 * i + j)] = r[i][j] * sc[j];
                t -= r[i][j] * sc[j] * double(c[j]);  // turn about the model's centre
            }
            a.m[std::size_t(4 * i + 3)] = t;
        }
        out.push_back(a);
    }
    return out;
}

std::vector<accel::Ray> camera_and_random(const accel::Bounds& b, std::size_t n) {
    std::vector<accel::Ray> rays;
    const Vec3f e = b.extent(), c = b.center();
    const float size = std::max({e.x, e.y, e.z});
    const Vec3f eye{c.x, c.y + 0.8f * size, c.z - 1.1f * size};
    const int side = int(std::sqrt(double(n)));
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            const Vec3f target{b.lo.x + e.x * (i + 0.5f) / float(side), c.y, b.lo.z + e.z * (j + 0.5f) / float(side)};
            rays.push_back({eye, 0.0f, target - eye, INFINITY});
        }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3f o{b.lo.x + e.x * u(rng), b.lo.y + e.y * u(rng), b.lo.z + e.z * u(rng)};
        rays.push_back({o, 0.0f, Vec3f{g(rng), g(rng), g(rng)}, INFINITY});
    }
    return rays;
}

int usage(const char* msg) {
    std::fprintf(stderr,
                 "arbor-bench instances: %s\nUsage: arbor-bench instances [--model OBJ] [--copies N] "
                 "[--accel NAME] [--rays N] [--repeat K] [--threads T] [--save-hits FILE]\n",
                 msg);
    return 2;
}

}  // namespace

namespace arbor::perf {

int instances_command(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) return usage((a + ": needs a value").c_str());
        const char* v = argv[++i];
        if (a == "--model")
            o.model = v;
        else if (a == "--accel")
            o.accel = v;
        else if (a == "--copies")
            o.copies = std::max(1, std::atoi(v));
        else if (a == "--rays")
            o.rays = std::size_t(std::max(64, std::atoi(v)));
        else if (a == "--repeat")
            o.repeat = std::max(1, std::atoi(v));
        else if (a == "--threads")
            o.threads = std::max(1, std::atoi(v));
        else if (a == "--save-hits")
            o.save_hits = v;
        else
            return usage(("unknown option " + a).c_str());
    }
    const auto kind = accel::parse_accel_kind(o.accel);
    if (!kind || *kind == accel::AccelKind::automatic) return usage("--accel: a structure name (bvh-sah, lbvh, ...)");
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));
    engine::Warnings warnings;
    const engine::Mesh mesh = engine::load_mesh(o.model, warnings);
    const std::size_t n = mesh.triangle_count();
    const std::vector<accel::Affine> ts = placements(mesh.bounds, o.copies);
    // The flattened scene: every copy's vertices carried over in double, rounded to float.
    engine::Mesh flat;
    for (const accel::Affine& t : ts) {
        const auto base = std::uint32_t(flat.vertex_count());
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
            const auto p = t.point(mesh.x[i], mesh.y[i], mesh.z[i]);
            flat.add_vertex(Vec3f{float(p[0]), float(p[1]), float(p[2])});
        }
        for (const std::uint32_t idx : mesh.indices) flat.indices.push_back(base + idx);
    }
    flat.compute_bounds();
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;
    const auto build_instanced = [&] {
        std::vector<accel::Bottom> bottoms(1);
        bottoms[0].mesh = std::make_unique<accel::InstanceMesh>();
        bottoms[0].mesh->x = mesh.x, bottoms[0].mesh->y = mesh.y, bottoms[0].mesh->z = mesh.z;
        bottoms[0].mesh->indices = mesh.indices, bottoms[0].mesh->bounds = mesh.bounds;
        bottoms[0].accel = accel::make_accel(*kind, bottoms[0].mesh->view(), cfg);
        std::vector<accel::Placement> ps;
        for (std::size_t k = 0; k < ts.size(); ++k) ps.push_back(accel::Placement::make(0, std::uint32_t(k), ts[k]));
        return std::make_unique<accel::InstanceAccel>(*kind, std::move(bottoms), std::move(ps));
    };
    std::vector<double> build_i, build_f;
    std::unique_ptr<accel::InstanceAccel> inst;
    std::unique_ptr<accel::Accel> ref;
    for (int r = 0; r < o.repeat; ++r) {
        const accel::Timer ti;
        inst = build_instanced();
        build_i.push_back(ti.ms());
        const accel::Timer tf;
        ref = accel::make_accel(*kind, flat.view(), cfg);
        build_f.push_back(tf.ms());
    }
    const std::vector<accel::Ray> rays = camera_and_random(flat.bounds, o.rays);
    std::vector<accel::Hit> a(rays.size()), b(rays.size());
    accel::trace_parallel(*ref, rays, a, accel::Query::closest);
    accel::trace_parallel(*inst, rays, b, accel::Query::closest);
    std::size_t differ = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
        differ += !accel::hits_agree(a[i], b[i]) || a[i].prim != b[i].prim, hits += a[i].is_hit();
    if (!o.save_hits.empty()) {
        std::FILE* out = std::fopen(o.save_hits.c_str(), "wb");
        if (!out) return usage(("--save-hits: cannot write " + o.save_hits).c_str());
        std::vector<accel::Hit> h(rays.size());
        for (const accel::Query q : {accel::Query::closest, accel::Query::any})
            for (const accel::TracePath p :
                 {accel::TracePath::scalar, accel::TracePath::single, accel::TracePath::packet}) {
                accel::trace_parallel(*inst, rays, h, q, p);
                std::fwrite(h.data(), sizeof(accel::Hit), h.size(), out);
            }
        std::fclose(out);
    }
#ifdef ARBOR_HAVE_EMBREE
    // Embree's two-level scene of the same copies (one mesh scene, an instance per transform) and
    // its flattened scene, on the same rays, with its fastest call of 1, 16 and 1M (Embree 3 only) on the
    // instanced scene (one timed pass each).
    std::unique_ptr<perf::EmbreePeer> e_inst, e_flat;
    std::vector<double> ebuild_i, ebuild_f;
    for (int r = 0; r < o.repeat; ++r) {
        e_inst = std::make_unique<perf::EmbreePeer>(mesh.view(), ts);
        ebuild_i.push_back(e_inst->build_ms());
        e_flat = std::make_unique<perf::EmbreePeer>(flat.view());
        ebuild_f.push_back(e_flat->build_ms());
    }
    std::vector<accel::Hit> e(rays.size());
    perf::EmbreeCall call = perf::EmbreeCall::single;
    double fastest = INFINITY;
    for (const perf::EmbreeCall c : {perf::EmbreeCall::single, perf::EmbreeCall::packet16, perf::EmbreeCall::stream}) {
        if (!perf::embree_has(c)) continue;  // no stream call in Embree 4
        const accel::Timer t;
        e_inst->trace_parallel(rays, e, accel::Query::closest, c, false);
        if (t.ms() < fastest) fastest = t.ms(), call = c;
    }
    std::size_t e_differ = 0, ef_differ = 0;
    e_inst->trace_parallel(rays, e, accel::Query::closest, call, false);
    for (std::size_t i = 0; i < rays.size(); ++i) e_differ += !accel::hits_agree(a[i], e[i]) || a[i].prim != e[i].prim;
    e_flat->trace_parallel(rays, e, accel::Query::closest, call, false);
    for (std::size_t i = 0; i < rays.size(); ++i) ef_differ += !accel::hits_agree(a[i], e[i]) || a[i].prim != e[i].prim;
    std::vector<double> etrace_i, etrace_f;
#endif
    std::vector<double> trace_i, trace_f;
    for (int r = 0; r < o.repeat; ++r) {
        const accel::Timer tf;
        accel::trace_parallel(*ref, rays, a, accel::Query::closest);
        trace_f.push_back(tf.ms());
        const accel::Timer ti;
        accel::trace_parallel(*inst, rays, b, accel::Query::closest);
        trace_i.push_back(ti.ms());
#ifdef ARBOR_HAVE_EMBREE
        const accel::Timer ei;
        e_inst->trace_parallel(rays, e, accel::Query::closest, call, false);
        etrace_i.push_back(ei.ms());
        const accel::Timer ef;
        e_flat->trace_parallel(rays, e, accel::Query::closest, call, false);
        etrace_f.push_back(ef.ms());
#endif
    }
    const double eff = double(n) * double(ts.size());
    const double mem_i = double(inst->stats().memory_bytes), mem_f = double(ref->stats().memory_bytes);
    const double mi = median(trace_i), mf = median(trace_f);
    std::printf(
        "model %s: %zu triangles x %zu copies = %.0f effective; %s; %zu rays (%zu camera + %zu random), "
        "%zu threads; %zu hits, %zu rays differ (by the rayfile.md rule or triangle)\n\n",
        o.model.c_str(), n, ts.size(), eff, o.accel.c_str(), rays.size(), rays.size() - o.rays, o.rays,
        std::size_t(o.threads), hits, differ);
    std::printf("| scene | build ms | trace ms | Mrays/s | bytes / unique tri | bytes / effective tri |\n");
    std::printf("|---|---:|---:|---:|---:|---:|\n");
    std::printf("| instanced (%zu copies) | %.1f | %.1f | %.2f | %.1f | %.2f |\n", ts.size(), median(build_i), mi,
                double(rays.size()) / mi * 1e-3, mem_i / double(n), mem_i / eff);
    std::printf("| flattened | %.1f | %.1f | %.2f | %.1f | %.2f |\n", median(build_f), mf,
                double(rays.size()) / mf * 1e-3, mem_f / double(n), mem_f / eff);
#ifdef ARBOR_HAVE_EMBREE
    const double ei = median(etrace_i), ef = median(etrace_f);
    const double emem_i = double(e_inst->memory_bytes()), emem_f = double(e_flat->memory_bytes());
    std::printf("| Embree instanced (call %s) | %.1f | %.1f | %.2f | %.1f | %.2f |\n",
                std::string(to_string(call)).c_str(), median(ebuild_i), ei, double(rays.size()) / ei * 1e-3,
                emem_i / double(n), emem_i / eff);
    std::printf("| Embree flattened (call %s) | %.1f | %.1f | %.2f | %.1f | %.2f |\n",
                std::string(to_string(call)).c_str(), median(ebuild_f), ef, double(rays.size()) / ef * 1e-3,
                emem_f / double(n), emem_f / eff);
#endif
    std::printf("\ninstanced trace throughput = %.2f x flattened; top level %zu bytes, bottom %zu bytes\n", mf / mi,
                inst->top_bytes(), inst->bottom_bytes());
#ifdef ARBOR_HAVE_EMBREE
    std::printf(
        "arbor / Embree trace throughput: instanced %.2f x, flattened %.2f x; Embree instanced = %.2f x its "
        "flattened; Embree's answers differ from arbor's flattened on %zu rays (instanced) and %zu (flattened)\n",
        ei / mi, ef / mf, ef / ei, e_differ, ef_differ);
#endif
    return differ * 1000 > rays.size() ? 1 : 0;
}

}  // namespace arbor::perf
