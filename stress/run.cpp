#include "stress/run.h"

#include "accel/factory/make_accel.h"
#include "accel/structures/kdtree_accel.h"

#include "accel/util/timer.h"
#include "accel/interface/trace.h"

#include <algorithm>
#include <stdexcept>

namespace arbor::stress {

namespace {

/// Single-threaded closest-hit time per ray: the fastest of up to 5 passes, fewer once 40 ms are spent.
double time_per_ray(const accel::Accel& a, std::span<const Ray> rays, accel::TracePath path) {
    if (rays.empty()) return 0.0;
    std::vector<Hit> hits(rays.size());
    double best = 0.0, spent = 0.0;
    for (int pass = 0; pass < 5 && spent < 40.0; ++pass) {
        const accel::Timer t;
        a.trace(rays, hits, {accel::Query::closest, path});
        const double ms = t.ms();
        best = pass == 0 ? ms : std::min(best, ms);
        spent += ms;
    }
    return best * 1e6 / double(rays.size());
}

}  // namespace

PreparedCase prepare(const StressCase& c) {
    PreparedCase p;
    p.c = &c;
    p.oracle = std::make_unique<Oracle>(c.mesh.view());
    p.answers = p.oracle->answers(c.rays);
    return p;
}

std::vector<accel::AccelKind> buildable_kinds() {
    // A kind is buildable when make_accel accepts it: structures still being written throw
    // std::invalid_argument, so new ones join the suite the day they are registered.
    const float x[3] = {0, 1, 0}, y[3] = {0, 0, 1}, z[3] = {0, 0, 0};
    const std::uint32_t idx[3] = {0, 1, 2};
    const accel::TriangleView one{x, y, z, idx};
    std::vector<accel::AccelKind> out;
    for (auto k : {accel::AccelKind::brute, accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh,
                   accel::AccelKind::kdtree}) {
        try {
            (void)accel::make_accel(k, one);
            out.push_back(k);
        } catch (const std::invalid_argument&) {
        }
    }
    return out;
}

std::vector<accel::TracePath> paths_of(const accel::Accel& a) {
    std::vector<accel::TracePath> out{accel::TracePath::scalar};
    for (auto p : {accel::TracePath::single, accel::TracePath::packet})
        if (a.offer().has(p)) out.push_back(p);
    return out;
}

std::vector<StressRow> run_case(const PreparedCase& p, accel::AccelKind kind, const accel::BuildConfig& cfg) {
    const StressCase& c = *p.c;
    const accel::Timer build_timer;
    const auto structure = accel::make_accel(kind, c.mesh.view(), cfg);
    const double build_ms = build_timer.ms();

    StressRow base;
    base.case_name = c.name;
    base.kind = kind;
    base.build_ms = build_ms;
    base.dropped = std::int64_t(structure->stats().dropped_nonfinite);
    if (c.expected_dropped >= 0 && base.dropped != c.expected_dropped)
        base.problem = "dropped " + std::to_string(base.dropped) + " non-finite triangles, expected " +
                       std::to_string(c.expected_dropped);

    // Statistics mode: work per ray, and none at all for untraceable rays.
    std::vector<Hit> counted_hits(c.rays.size());
    accel::TraceCounters counters;
    if (structure->offer().counts) {
        structure->trace(c.rays, counted_hits, {accel::Query::closest, accel::TracePath::scalar, {}, {}, &counters});
        base.counted = true;
        const double n = double(std::max<std::size_t>(c.rays.size(), 1));
        base.nodes_per_ray = double(counters.nodes_visited) / n;
        base.triangles_per_ray = double(counters.triangles_tested) / n;
        std::vector<Ray> untraceable;
        for (const Ray& r : c.rays)
            if (!accel::ray_is_traceable(r)) untraceable.push_back(r);
        std::vector<Hit> h(untraceable.size());
        accel::TraceCounters bad;
        for (const auto q : {accel::Query::closest, accel::Query::any})
            structure->trace(untraceable, h, {q, accel::TracePath::scalar, {}, {}, &bad});
        if (bad.nodes_visited + bad.triangles_tested != 0) {
            if (!base.problem.empty()) base.problem += "; ";
            base.problem += std::to_string(untraceable.size()) + " untraceable rays visited " +
                            std::to_string(bad.nodes_visited) + " nodes and " + std::to_string(bad.triangles_tested) + " triangles";
        }
    }

    std::vector<StressRow> rows;
    const auto judge_paths = [&](const accel::Accel& a, bool with_scalar) {
        const auto* kd = dynamic_cast<const accel::KdTreeAccel*>(&a);
        for (accel::TracePath path : paths_of(a)) {
            if (path == accel::TracePath::scalar && !with_scalar) continue;
            StressRow row = base;
            row.path = path;
            if (kd && path != accel::TracePath::scalar) row.walk = accel::kd_walk_name(kd->walk());
            std::vector<Hit> closest(c.rays.size()), any(c.rays.size());
            accel::trace_parallel(a, c.rays, closest, accel::Query::closest, path, 256);
            accel::trace_parallel(a, c.rays, any, accel::Query::any, path, 256);
            row.tally = judge(c, *p.oracle, p.answers, closest, any);
            row.ns_per_ray = time_per_ray(a, c.rays, path);
            rows.push_back(std::move(row));
        }
    };
    judge_paths(*structure, true);
    if (has_parity(c)) {
        // The all-hits lists (one walk per structure, whatever the path) join its first row.
        struct Lists final : accel::HitSink {
            std::vector<std::vector<Hit>> lists;
            void take(std::size_t i, std::span<Hit> hits) override { lists[i].assign(hits.begin(), hits.end()); }
        } sink;
        sink.lists.resize(c.rays.size());
        structure->trace_all(c.rays, sink);
        judge_crossings(c, sink.lists, rows.front().tally);
    }
    if (kind == accel::AccelKind::kdtree && cfg.layouts != accel::Layouts::scalar)
        for (const accel::KdWalk walk : {accel::KdWalk::tight_cells, accel::KdWalk::cells, accel::KdWalk::ropes}) {
            if (walk == cfg.kd_blocks.walk) continue;
            accel::BuildConfig other = cfg;
            other.kd_blocks.walk = walk;
            judge_paths(*accel::make_accel(kind, c.mesh.view(), other), false);
        }
    return rows;
}

}  // namespace arbor::stress
