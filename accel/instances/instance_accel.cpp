#include "accel/instances/instance_accel.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "accel/factory/make_accel.h"

namespace arbor::accel {

namespace {
/// Whether a placement whose box the ray enters at `enter` lies wholly behind the ray's best hit
/// so far (`best`, +inf for none): then it can hold no closer hit, nor a tie. The margin of 1e-6
/// covers the rounding of the hit's t by the triangle test.
bool behind(double enter, float best) { return enter - 1e-6 * std::fabs(enter) > double(best); }
}  // namespace

InstanceAccel::InstanceAccel(AccelKind kind, std::vector<Bottom> bottoms, std::vector<Placement> placements)
    : Accel(kind), bottoms_(std::move(bottoms)), placements_(std::move(placements)) {
    std::uint64_t first = 0;
    std::vector<Bounds> boxes(placements_.size());
    scale_.resize(placements_.size());
    for (std::size_t k = 0; k < placements_.size(); ++k) {
        Placement& p = placements_[k];
        const Bottom& b = bottoms_.at(p.geom);
        p.first = std::uint32_t(first);
        first += b.mesh->indices.size() / 3;
        if (first >= invalid_prim)
            throw std::length_error("instances: the placed triangles number 2^32 - 1 or more (" +
                                    std::to_string(first) + " by instance " + std::to_string(p.id) + ")");
        boxes[k] = p.identity ? b.mesh->bounds : transform_bounds(p.to_world, b.mesh->bounds);
        bounds_.grow(boxes[k]);
        scale_[k] = p.identity ? 1.0 : p.to_world.similarity_scale().value_or(0.0);
    }
    top_ = TopBvh::build(boxes);
    seams_.resize(bottoms_.size());
    for (std::size_t g = 0; g < bottoms_.size(); ++g) {
        if (!bottoms_[g].mesh) continue;
        seams_[g] = find_seams(bottoms_[g].mesh->view());
        const std::size_t n = bottoms_[g].mesh->indices.size() / 3;
        if (seams_[g].tris.size() > std::max(seam_limit, n / 8)) seams_[g] = SeamSet{};
    }
    placed_seams_.resize(placements_.size());
    for (std::size_t k = 0; k < placements_.size(); ++k) placed_seams_[k] = world_seams(placements_[k]);
    // The paths of the bottoms (each falls back by itself for a path it lacks); the counted mode
    // is not offered (it counts within one structure).
    for (const Bottom& b : bottoms_)
        if (b.accel) {
            offer_ = b.accel->offer();
            break;
        }
    offer_.counts = false;
    if (!bounds_.empty()) {
        const Vec3f e = bounds_.extent();
        offer_.scene_diagonal = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    }
    stats_.triangles = first;
    for (const Bottom& b : bottoms_)
        if (b.accel) {
            stats_.build_ms += b.accel->stats().build_ms;
            stats_.nodes += b.accel->stats().nodes;
            stats_.leaves += b.accel->stats().leaves;
            stats_.dropped_nonfinite += b.accel->stats().dropped_nonfinite;
        }
    stats_.memory_bytes = top_bytes() + bottom_bytes() + seam_bytes();
}

std::size_t InstanceAccel::top_bytes() const {
    return top_.memory_bytes() + placements_.size() * (sizeof(Placement) + sizeof(double) + sizeof(WorldSeams));
}

std::size_t InstanceAccel::bottom_bytes() const {
    std::size_t s = 0;
    for (const Bottom& b : bottoms_)
        if (b.accel) s += b.accel->stats().memory_bytes;
    return s;
}

InstanceAccel::WorldSeams InstanceAccel::world_seams(const Placement& p) const {
    WorldSeams w;
    const SeamSet& seams = seams_[p.geom];
    // An identity placement is tested in world space already (its object ray is the world ray).
    if (p.identity || seams.tris.empty()) return w;
    const InstanceMesh& m = *bottoms_[p.geom].mesh;
    w.mesh = std::make_unique<InstanceMesh>();
    for (const std::uint32_t t : seams.tris)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = m.indices[3 * std::size_t(t) + std::size_t(c)];
            const auto q = p.to_world.point(m.x[v], m.y[v], m.z[v]);
            w.mesh->indices.push_back(std::uint32_t(w.mesh->x.size()));
            w.mesh->x.push_back(float(q[0])), w.mesh->y.push_back(float(q[1])), w.mesh->z.push_back(float(q[2]));
        }
    // Traced on the batch's own path (the SIMD layout answers every path with the reference
    // path's bits): on the scalar path alone, the seams of the bunny's copies took half the time
    // of its instanced trace.
    BuildConfig cfg;
    cfg.layouts = Layouts::simd;
    w.accel = make_accel(seams.tris.size() <= 8 ? AccelKind::brute : AccelKind::bvh_sah, w.mesh->view(), cfg);
    return w;
}

std::size_t InstanceAccel::seam_bytes() const {
    std::size_t s = 0;
    for (const WorldSeams& w : placed_seams_)
        if (w.accel)
            s += w.accel->stats().memory_bytes + w.mesh->x.size() * 3 * sizeof(float) + w.mesh->indices.size() * 4;
    return s;
}

void InstanceAccel::trace_seams(std::size_t k, std::span<const Ray> rays, std::span<Hit> hits, const Groups& g,
                                const TraceRequest& req) const {
    const WorldSeams& w = placed_seams_[k];
    if (!w.accel) return;
    const Placement& p = placements_[k];
    const std::vector<std::uint32_t>& tris = seams_[p.geom].tris;
    const bool any = req.query == Query::any;
    thread_local std::vector<Ray> world;
    thread_local std::vector<Hit> got;
    thread_local std::vector<std::uint32_t> which;
    world.clear(), which.clear();
    for (std::uint32_t j = g.start[k]; j < g.start[k + 1]; ++j) {
        const std::uint32_t i = g.order[j];
        if (any ? hits[i].is_hit() : behind(g.enter[j], hits[i].t)) continue;
        Ray r = rays[i];
        r.tfar = std::min(r.tfar, hits[i].t);
        world.push_back(r);
        which.push_back(i);
    }
    if (world.empty()) return;
    got.resize(world.size());
    w.accel->trace(world, got, req);
    for (std::size_t j = 0; j < world.size(); ++j) {
        const Hit& h = got[j];
        if (!h.is_hit()) continue;
        Hit& best = hits[which[j]];
        const std::uint32_t prim = p.first + tris[h.prim];
        if (any || simd::closer(h.t, prim, best)) best = {h.t, prim, h.u, h.v};
    }
}

std::size_t InstanceAccel::placement_of(std::uint32_t prim) const {
    const auto it = std::upper_bound(placements_.begin(), placements_.end(), prim,
                                     [](std::uint32_t v, const Placement& p) { return v < p.first; });
    return std::size_t(it - placements_.begin()) - 1;
}

Ray InstanceAccel::to_object(const Placement& p, const Ray& r) const {
    if (p.identity) return r;
    const auto o = p.to_object.point(r.org.x, r.org.y, r.org.z);
    const auto d = p.to_object.vector(r.dir.x, r.dir.y, r.dir.z);
    return {{float(o[0]), float(o[1]), float(o[2])}, r.tnear, {float(d[0]), float(d[1]), float(d[2])}, r.tfar};
}

void InstanceAccel::group(std::span<const Ray> rays, Groups& g) const {
    thread_local std::vector<std::uint32_t> pairs_place, pairs_ray;
    thread_local std::vector<double> pairs_t, enter;
    pairs_place.clear(), pairs_ray.clear(), pairs_t.clear();
    enter.assign(placements_.size(), 0.0);
    // The rays' slab constants (simd/ray_box.h) worked out a packet at a time (bit for bit those of
    // simd::slab_ray: the packet code's are tested lane by lane against it), then each ray walks
    // the top level on its own, in ray order.
    using P = simd::FloatV;
    constexpr std::size_t width = P::size;
    for (std::size_t base = 0; base < rays.size(); base += width) {
        const simd::RayPacket<P> pk =
            simd::load_packet_boxes<P, Ray>(rays.subspan(base, std::min(width, rays.size() - base)));
        alignas(64) float f[9][width];
        std::uint32_t near_is_hi[3];
        for (int k = 0; k < 3; ++k) {
            simd::store_lanes(pk.org[k], f[k]);
            simd::store_lanes(pk.rcp_near[k], f[3 + k]);
            simd::store_lanes(pk.rcp_far[k], f[6 + k]);
            near_is_hi[k] = simd::to_bits(pk.near_is_hi[k]);
        }
        const std::uint32_t plain = simd::to_bits(pk.active & pk.plain_lanes);
        // Untraceable rays (simd/ray.h) are not active: they meet nothing.
        for (std::uint32_t live = simd::to_bits(pk.active); live != 0; live &= live - 1) {
            const auto l = std::size_t(std::countr_zero(live));
            const std::size_t i = base + l;
            const Ray& r = rays[i];
            simd::SlabRay s;
            s.org = {f[0][l], f[1][l], f[2][l]};
            s.rcp_near = {f[3][l], f[4][l], f[5][l]};
            s.rcp_far = {f[6][l], f[7][l], f[8][l]};
            for (int k = 0; k < 3; ++k) s.near_is_hi[k] = int(near_is_hi[k] >> l & 1u);
            const double len =
                std::sqrt(double(r.dir.x) * r.dir.x + double(r.dir.y) * r.dir.y + double(r.dir.z) * r.dir.z);
            top_.ray_items(s, r.tnear, r.tfar, (plain >> l & 1u) != 0, [&](std::uint32_t k, double t0) {
                pairs_place.push_back(k);
                pairs_ray.push_back(std::uint32_t(i));
                pairs_t.push_back(t0);
                enter[k] += t0 * len;
            });
        }
    }
    // Counting sort by placement; stable, so each group keeps the rays' order (packets stay coherent).
    g.start.assign(placements_.size() + 1, 0);
    for (const std::uint32_t k : pairs_place) ++g.start[k + 1];
    for (std::size_t k = 0; k < placements_.size(); ++k) g.start[k + 1] += g.start[k];
    g.order.resize(pairs_place.size());
    g.enter.resize(pairs_place.size());
    thread_local std::vector<std::uint32_t> fill;
    fill.assign(g.start.begin(), g.start.end() - 1);
    for (std::size_t j = 0; j < pairs_place.size(); ++j) {
        const std::uint32_t at = fill[pairs_place[j]]++;
        g.order[at] = pairs_ray[j], g.enter[at] = pairs_t[j];
    }
    g.visit.clear();
    for (std::size_t k = 0; k < placements_.size(); ++k)
        if (g.start[k + 1] > g.start[k]) {
            g.visit.push_back(std::uint32_t(k));
            enter[k] /= double(g.start[k + 1] - g.start[k]);
        }
    // Ties by placement number: the order, and so the answers, do not depend on anything else.
    std::sort(g.visit.begin(), g.visit.end(),
              [&](std::uint32_t a, std::uint32_t b) { return enter[a] < enter[b] || (enter[a] == enter[b] && a < b); });
}

void InstanceAccel::run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
                        TraceCounters*) const {
    std::fill(hits.begin(), hits.end(), Hit{});
    thread_local Groups g;
    group(rays, g);
    thread_local std::vector<Ray> obj;
    thread_local std::vector<Hit> got;
    thread_local std::vector<std::uint32_t> which;
    const bool any = query == Query::any;
    const TraceRequest req{query, path};
    for (const std::uint32_t k : g.visit) {
        const Placement& p = placements_[k];
        obj.clear(), which.clear();
        for (std::uint32_t j = g.start[k]; j < g.start[k + 1]; ++j) {
            const std::uint32_t i = g.order[j];
            if (any ? hits[i].is_hit() : behind(g.enter[j], hits[i].t)) continue;
            Ray r = to_object(p, rays[i]);
            // A closest-hit ray looks no farther than its best hit so far (ties at t are still
            // tested and settled by the global numbers below).
            r.tfar = std::min(r.tfar, hits[i].t);
            obj.push_back(r);
            which.push_back(i);
        }
        if (obj.empty()) continue;
        got.resize(obj.size());
        bottoms_[p.geom].accel->trace(obj, got, req);
        for (std::size_t j = 0; j < obj.size(); ++j) {
            const Hit& h = got[j];
            if (!h.is_hit()) continue;
            Hit& best = hits[which[j]];
            const std::uint32_t prim = p.first + h.prim;
            if (any || simd::closer(h.t, prim, best)) best = {h.t, prim, h.u, h.v};
        }
        trace_seams(k, rays, hits, g, req);
    }
}

namespace {
/// Collects a bottom's crossings as (ray, hit) pairs with global triangle numbers.
class Collect final : public HitSink {
public:
    /// `skip`: per triangle of the mesh, 1 for those answered elsewhere (null: none); `map`: the
    /// mesh's triangle number of each prim the structure reports (null: the same).
    Collect(std::vector<std::pair<std::uint32_t, Hit>>& out, const std::vector<std::uint32_t>& which,
            std::uint32_t first, const std::uint8_t* skip, const std::uint32_t* map)
        : out_(out), which_(which), first_(first), skip_(skip), map_(map) {}
    void take(std::size_t j, std::span<Hit> list) override {
        for (const Hit& h : list) {
            const std::uint32_t tri = map_ ? map_[h.prim] : h.prim;
            if (!skip_ || !skip_[tri]) out_.push_back({which_[j], {h.t, first_ + tri, h.u, h.v}});
        }
    }

private:
    std::vector<std::pair<std::uint32_t, Hit>>& out_;
    const std::vector<std::uint32_t>& which_;
    std::uint32_t first_;
    const std::uint8_t* skip_;
    const std::uint32_t* map_;
};
}  // namespace

void InstanceAccel::trace_all(std::span<const Ray> rays, HitSink& sink) const {
    thread_local Groups g;
    group(rays, g);
    thread_local std::vector<std::pair<std::uint32_t, Hit>> all;
    thread_local std::vector<Ray> obj;
    thread_local std::vector<std::uint32_t> which;
    all.clear();
    for (std::size_t k = 0; k < placements_.size(); ++k) {
        if (g.start[k] == g.start[k + 1]) continue;
        const Placement& p = placements_[k];
        obj.clear(), which.clear();
        for (std::uint32_t j = g.start[k]; j < g.start[k + 1]; ++j) {
            obj.push_back(to_object(p, rays[g.order[j]]));
            which.push_back(g.order[j]);
        }
        const WorldSeams& w = placed_seams_[k];
        // The seam triangles of a moved placement are counted in world space only, once.
        Collect c(all, which, p.first, w.accel ? seams_[p.geom].flag.data() : nullptr, nullptr);
        bottoms_[p.geom].accel->trace_all(obj, c);
        if (w.accel) {
            obj.clear();
            for (std::uint32_t j = g.start[k]; j < g.start[k + 1]; ++j) obj.push_back(rays[g.order[j]]);
            Collect s(all, which, p.first, nullptr, seams_[p.geom].tris.data());
            w.accel->trace_all(obj, s);
        }
    }
    // Ray by ray, in (t, global number) order: each placement's triangles once (each bottom drops
    // its own repeats; placements have disjoint numbers).
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
        return a.first < b.first ||
               (a.first == b.first &&
                (a.second.t < b.second.t || (a.second.t == b.second.t && a.second.prim < b.second.prim)));
    });
    thread_local std::vector<Hit> list;
    std::size_t j = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        list.clear();
        for (; j < all.size() && all[j].first == i; ++j) list.push_back(all[j].second);
        sink.take(i, list);
    }
}

void InstanceAccel::nearest_in(const Placement& p, const Vec3f& point, double& best2, PointHit& best) const {
    const std::size_t k = std::size_t(&p - placements_.data());
    const InstanceMesh& m = *bottoms_[p.geom].mesh;
    const double pw[3] = {point.x, point.y, point.z};
    const auto offer = [&](double d2, std::uint32_t local, double u, double v, const std::array<double, 3>& q) {
        const std::uint32_t prim = p.first + local;
        if (d2 < best2 || (d2 == best2 && prim < best.prim)) {
            best2 = d2;
            best.distance = float(std::sqrt(d2));
            best.prim = prim;
            best.point = {float(q[0]), float(q[1]), float(q[2])};
            best.u = float(u), best.v = float(v);
        }
    };
    if (p.identity) {
        // The mesh's own answer, bit for bit (its distance is measured in world space already).
        PointHit h;
        const float reach = best2 == INFINITY ? INFINITY : float(std::sqrt(best2)) * (1.0f + 0x1p-20f);
        bottoms_[p.geom].accel->closest_points({&point, 1}, reach, {&h, 1});
        if (!h.is_hit()) return;
        const double d2 = double(h.distance) * double(h.distance);
        const std::uint32_t prim = p.first + h.prim;
        if (d2 < best2 || (d2 == best2 && prim < best.prim)) best2 = d2, best = h, best.prim = prim;
        return;
    }
    const auto world_corner = [&](std::uint32_t tri, int c) {
        const std::uint32_t vi = m.indices[3 * tri + std::uint32_t(c)];
        const auto w = p.to_world.point(m.x[vi], m.y[vi], m.z[vi]);
        return Vec3d{w[0], w[1], w[2]};
    };
    const auto measure = [&](std::uint32_t tri) {
        const Vec3d a = world_corner(tri, 0), b = world_corner(tri, 1), c = world_corner(tri, 2);
        const TrianglePoint t = closest_on_triangle(Vec3d{pw[0], pw[1], pw[2]}, a, b, c);
        const Vec3d q = a * (1.0 - t.u - t.v) + b * t.u + c * t.v;
        offer(t.dist2, tri, t.u, t.v, {q.x, q.y, q.z});
    };
    if (scale_[k] > 0.0) {
        // A similarity: distances scale by s in every direction, so the object-space nearest is
        // the world nearest; its reach is the world reach over s (grown a little: s is known to 1e-6).
        const auto o = p.to_object.point(pw[0], pw[1], pw[2]);
        const Vec3f po{float(o[0]), float(o[1]), float(o[2])};
        const float reach = best2 == INFINITY ? INFINITY : float(std::sqrt(best2) / scale_[k] * (1.0 + 1e-5));
        PointHit h;
        bottoms_[p.geom].accel->closest_points({&po, 1}, reach, {&h, 1});
        if (h.is_hit()) measure(h.prim);
        return;
    }
    // Non-uniform scale or shear: object distances mislead, so every finite triangle is measured
    // in world space (exact, and O(triangles of the mesh) per point that reaches the placement).
    const TriangleView view = m.view();
    for (std::uint32_t tri = 0; tri < view.triangle_count(); ++tri)
        if (view.triangle_is_finite(tri)) measure(tri);
}

void InstanceAccel::closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const {
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3f& p = points[i];
        out[i] = PointHit{};
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) || !(max_distance >= 0.0f)) continue;
        double best2 = double(max_distance) * double(max_distance);
        PointHit best;
        const double pd[3] = {p.x, p.y, p.z};
        top_.nearest_items(pd, best2, [&](std::uint32_t k) { nearest_in(placements_[k], p, best2, best); });
        out[i] = best;
    }
}

}  // namespace arbor::accel
