/// arbor::Scene::update_vertices: new positions for a mesh, and the structure refit or rebuilt
/// (accel/select/refit_select.h decides and says why; docs/refit.md).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "accel/factory/make_accel.h"
#include "accel/select/auto_model.h"
#include "accel/select/auto_select.h"
#include "accel/select/job_shape.h"
#include "accel/select/reason_words.h"
#include "accel/select/refit_select.h"
#include "accel/util/timer.h"
#include "api/scene_impl.h"

namespace arbor {

namespace {

using Kind = Error::Kind;
/// The bracket's times stay in milliseconds, two decimals below 10 ms (scripts/bench_refit.py reads them).
constexpr accel::MsWords in_ms{false, false};

/// Grain of the passes over vertices and triangles below (each is one streaming pass: in parallel,
/// they keep a 1M-triangle update's own work small beside the refit).
constexpr std::size_t grain = 16384;

/// Whether any triangle of [first, end) has a non-finite corner.
bool any_nonfinite(const accel::TriangleView& view, std::size_t first, std::size_t end) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(first, end, grain), false,
        [&](const tbb::blocked_range<std::size_t>& r, bool found) {
            for (std::size_t t = r.begin(); !found && t != r.end(); ++t) found = !view.triangle_is_finite(t);
            return found;
        },
        [](bool a, bool b) { return a || b; });
}

/// The first vertex of `count` (x, y, z at `stride` bytes) with a non-finite coordinate, or count.
std::size_t first_nonfinite(const unsigned char* bytes, std::size_t count, std::size_t stride) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, count, grain), count,
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t first) {
            for (std::size_t i = r.begin(); i != r.end() && i < first; ++i) {
                float p[3];
                std::memcpy(p, bytes + i * stride, sizeof p);
                if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return i;
            }
            return first;
        },
        [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

/// The box of the finite triangles (the ones a structure keeps): min and max are exact, so the
/// parallel reduction gives the same box for any thread count.
accel::Bounds finite_bounds(const accel::TriangleView& view) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, view.triangle_count(), grain), accel::Bounds{},
        [&](const tbb::blocked_range<std::size_t>& r, accel::Bounds box) {
            for (std::size_t t = r.begin(); t != r.end(); ++t)
                if (view.triangle_is_finite(t)) box.grow(view.triangle_bounds(t));
            return box;
        },
        [](accel::Bounds a, const accel::Bounds& b) {
            a.grow(b);
            return a;
        });
}

/// Trace time per ray on a fresh tree of `s`'s structure, ns: measured from the answers since the
/// last build or update (their mean time, divided by the SAH ratio of the tree they ran on), else
/// the prediction of auto's cost model for closest hits of `rays` incoherent rays.
double fresh_ns_per_ray(const Scene::Impl& s, accel::AccelKind kind, double rays, std::string& source) {
    const std::uint64_t n = s.answered.load(), ns = s.answer_ns.load();
    if (n > 0 && ns > 0) {
        source = "measured";
        return double(ns) / double(n) / s.sah_ratio;
    }
    const accel::AutoModel& model = accel::builtin_auto_model();
    const accel::TracePath paths[] = {accel::TracePath::single, accel::TracePath::packet, accel::TracePath::scalar};
    for (const accel::TracePath p : paths) {
        if (!model.has(kind, p)) continue;
        accel::RayShape shape;
        shape.rays = rays;
        shape.coherent = shape.together = 0.0;
        source = "predicted by auto's model";
        return model.ns_per_ray(kind, p, accel::scene_shape(s.mesh.view()), shape,
                                double(std::max(1, s.threads ? s.threads : accel::active_trace_threads())));
    }
    source = "no model of it";
    return 0.0;
}

}  // namespace

void Scene::update_vertices(std::uint32_t geom, const float* vertices, std::size_t vertex_count, std::size_t stride,
                            const UpdateOptions& options) {
    guarded([&] {
        Impl& s = *impl_;
        const std::lock_guard lock(s.build_mutex);
        const std::size_t meshes = s.first_prim.size();
        if (geom >= meshes)
            throw Error(Kind::invalid_argument, "update_vertices: geom " + std::to_string(geom) +
                                                    " is not in the scene (" + std::to_string(meshes) + " meshes)");
        const auto mode = accel::parse_update_mode(options.mode);
        if (!mode)
            throw Error(Kind::invalid_argument,
                        "update_vertices: mode '" + options.mode + "' (expected auto, refit or rebuild)");
        if (!(options.rays == options.rays) || std::isinf(options.rays))
            throw Error(Kind::invalid_argument,
                        "update_vertices: rays must be a finite number (negative: the rays answered since the last "
                        "build or update)");
        if (!s.instances.empty())
            throw Error(Kind::invalid_argument,
                        "update_vertices: the scene has instances; moving a mesh under instances is not offered yet "
                        "(set_transform moves an instance)");
        const std::size_t first_v = s.first_vertex[geom];
        const std::size_t end_v = geom + 1 < meshes ? s.first_vertex[geom + 1] : s.mesh.vertex_count();
        if (vertex_count != end_v - first_v)
            throw Error(Kind::invalid_argument, "update_vertices: vertices: expected " +
                                                    std::to_string(end_v - first_v) + " (mesh " + std::to_string(geom) +
                                                    "'s vertex count), got " + std::to_string(vertex_count));
        if (vertex_count != 0 && vertices == nullptr)
            throw Error(Kind::invalid_argument, "update_vertices: vertices is null");
        if (vertex_count != 0 && stride < 3 * sizeof(float))
            throw Error(Kind::invalid_argument,
                        "update_vertices: stride " + std::to_string(stride) + " is below 12 bytes (x, y, z floats)");
        // The passes below run on the scene's threads (a scene never built: on the caller's).
        const auto in_arena = [&](auto&& f) {
            if (s.arena)
                s.arena->execute(f);
            else
                f();
        };
        // Every coordinate checked before anything changes: a bad array leaves the scene as it was.
        const auto* bytes = reinterpret_cast<const unsigned char*>(vertices);
        std::size_t bad = vertex_count;
        in_arena([&] { bad = first_nonfinite(bytes, vertex_count, stride); });
        if (bad != vertex_count) {
            float p[3];
            std::memcpy(p, bytes + bad * stride, sizeof p);
            throw Error(Kind::invalid_argument, "update_vertices: vertices[" + std::to_string(bad) +
                                                    "] is not finite (" + std::to_string(p[0]) + ", " +
                                                    std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
        }
        const std::size_t first_t = s.first_prim[geom];
        const std::size_t end_t = geom + 1 < meshes ? s.first_prim[geom + 1] : s.mesh.triangle_count();
        const accel::TriangleView view = s.mesh.view();
        bool gained = false;
        in_arena([&] {
            // A triangle left out of the tree for a non-finite corner is finite now: a refit cannot
            // add it (only a tree that left some out needs the look).
            if (s.ready && s.accel && s.accel->stats().dropped_nonfinite != 0)
                gained = any_nonfinite(view, first_t, end_t);
            // In place: the spans of `view` (and a brute structure's view) stay valid.
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, vertex_count, grain), [&](const tbb::blocked_range<std::size_t>& r) {
                    for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        float p[3];
                        std::memcpy(p, bytes + i * stride, sizeof p);
                        s.mesh.x[first_v + i] = p[0], s.mesh.y[first_v + i] = p[1], s.mesh.z[first_v + i] = p[2];
                    }
                });
        });
        // The scene's box: a refit's root box, else one pass over the triangles.
        const auto update_bounds = [&](const accel::Bounds* refit_box) {
            if (refit_box)
                s.bounds = *refit_box;
            else
                in_arena([&] { s.bounds = finite_bounds(view); });
            s.mesh.bounds = s.bounds;
        };

        // The winding-number tree holds the old positions: made again by the next winding query.
        s.winding.reset();
        s.winding_ready = false;
        const double rays = options.rays >= 0.0 ? options.rays : double(s.answered.load());
        const std::string rays_source = options.rays >= 0.0 ? "given" : "answered since the last build or update";
        if (!s.ready || !s.accel) {
            update_bounds(nullptr);
            s.update_action = "none";
            s.update_reason = "none: not built yet; the next query builds the structure";
            return;
        }
        const auto kind = *accel::parse_accel_kind(s.accel_name);
        std::string why_not(s.accel->refit_unsupported());
        if (why_not.empty() && gained)
            why_not = "triangles with a non-finite corner, left out of the tree, are finite now";
        bool rebuild = *mode == accel::UpdateMode::rebuild || !why_not.empty();
        std::string timing;  // what the structure's own work took, for the reason's end
        std::string reason;
        if (!why_not.empty())
            reason = accel::unsupported_reason(why_not);
        else if (*mode == accel::UpdateMode::rebuild)
            reason = accel::forced_reason(*mode, nullptr);
        if (!rebuild) {
            accel::RefitResult r;
            s.arena->execute([&] { r = s.accel->refit(view); });
            if (*mode == accel::UpdateMode::refit) {
                reason = accel::forced_reason(*mode, &r);
            } else {
                accel::RefitJob job;
                job.refit = r;
                job.rays = rays;
                job.rays_source = rays_source;
                job.ns_per_ray = rays > 0.0 ? fresh_ns_per_ray(s, kind, rays, job.ns_source) : 0.0;
                job.rebuild_ms = s.build_ms;
                const accel::RefitChoice c = accel::choose_refit(job);
                rebuild = c.rebuild;
                reason = c.reason;
            }
            s.sah_ratio = r.ratio();
            timing = "the refit took " + accel::ms_words(r.ms, in_ms);
            if (!rebuild) update_bounds(&r.bounds);
        }
        if (rebuild) {
            accel::BuildConfig cfg;
            cfg.max_memory = s.options.max_memory;
            cfg.layouts = accel::Layouts::simd;  // as build() makes it
            cfg.compact = s.options.compact;
            s.ready = false;
            s.accel.reset();
            update_bounds(nullptr);
            s.arena->execute([&] { s.accel = accel::make_accel(kind, view, cfg); });
            s.build_ms = s.accel->stats().build_ms;
            timing += std::string(timing.empty() ? "the rebuild took " : ", the rebuild ") +
                      accel::ms_words(s.build_ms, in_ms);
            s.sah_ratio = 1.0;
            s.ready = true;
        }
        s.answered = 0, s.answer_ns = 0;
        s.update_action = rebuild ? "rebuild" : "refit";
        s.update_reason = reason + " [" + timing + "]";
    });
}

void Scene::update_vertices(std::uint32_t geom, const std::vector<float>& vertices, const UpdateOptions& options) {
    if (vertices.size() % 3 != 0)
        throw Error(Kind::invalid_argument, "update_vertices: vertices must hold whole x, y, z triples (size " +
                                                std::to_string(vertices.size()) + ")");
    update_vertices(geom, vertices.data(), vertices.size() / 3, 3 * sizeof(float), options);
}

std::string Scene::update_action() const { return impl_->update_action; }
std::string Scene::update_reason() const { return impl_->update_reason; }

}  // namespace arbor
