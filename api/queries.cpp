/// arbor::Scene's batch queries: the caller's arrays are read in chunks (api/batch.h), each chunk
/// turned into accel::Ray records or points in a per-thread buffer, answered by one call of the
/// structure, and written back with geometry ids. Winding numbers, inside by method, signed
/// distances and closed(): winding.cpp.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "accel/interface/inside.h"
#include "accel/interface/path_policy.h"
#include "accel/interface/path_race.h"
#include "api/batch.h"
#include "api/point_order.h"
#include "api/scene_impl.h"

namespace arbor {

namespace {

/// Rays per chunk: as accel::trace_parallel (whole 8x8 tiles of a camera stay in one chunk).
constexpr std::size_t ray_chunk = 1024;

float read_float(const float* base, std::size_t stride, std::size_t i) {
    float v;
    std::memcpy(&v, reinterpret_cast<const unsigned char*>(base) + i * stride, sizeof v);
    return v;
}

accel::Ray ray_at(const RayArrays& r, std::size_t i) {
    return {read_vec3(r.origins, r.origin_stride, i), r.tnear ? read_float(r.tnear, r.tnear_stride, i) : r.tnear_value,
            read_vec3(r.directions, r.direction_stride, i), r.tfar ? read_float(r.tfar, r.tfar_stride, i) : r.tfar_value};
}

/// Whether the arrays are already accel::Ray records (origin, tnear, direction, tfar: 32 bytes each,
/// as arbor::Ray and Python's read_rays hold them), so the structure can read them in place.
bool are_records(const RayArrays& r) {
    static_assert(sizeof(accel::Ray) == 8 * sizeof(float) && alignof(accel::Ray) == alignof(float));
    constexpr std::size_t rec = sizeof(accel::Ray);
    return r.origin_stride == rec && r.direction_stride == rec && r.tnear_stride == rec && r.tfar_stride == rec &&
           r.directions == r.origins + 4 && r.tnear == r.origins + 3 && r.tfar == r.origins + 7 &&
           reinterpret_cast<std::uintptr_t>(r.origins) % alignof(accel::Ray) == 0;
}

/// The chunk's rays: in place when they are records, else converted in this thread's buffer.
std::span<const accel::Ray> load_rays(const RayArrays& r, std::size_t begin, std::size_t end) {
    if (are_records(r)) return {reinterpret_cast<const accel::Ray*>(r.origins) + begin, end - begin};
    thread_local std::vector<accel::Ray> buf;
    buf.resize(end - begin);
    for (std::size_t i = begin; i < end; ++i) buf[i - begin] = ray_at(r, i);
    return buf;
}

/// The request for a whole batch: one path decision from the batch's own rays, as `arbor trace`
/// makes it for a ray file without --accel auto (accel/interface/path_policy.h: what the structure
/// offers and the rays' coherence say), read from the few rays the policy looks at. No path is
/// pinned: a scene's auto pick saw no rays, and a path it guessed would send camera and shadow
/// batches down the single-ray path at half the packet path's speed. Every chunk then runs on
/// that path (a raced batch: on the race's winner, after its race chunks): the chunks do not each
/// ask the policy, and the answer does not depend on where the chunk boundaries fall relative to
/// the policy's sample.
/// A batch the measure cannot call (diffuse rays) is raced instead (accel/interface/path_race.h):
/// `race` says so.
accel::TraceRequest batch_request(const accel::Accel& a, const RayArrays& r, accel::Query q, bool& race) {
    accel::TraceRequest req{q, accel::TracePath::best, accel::RayHint::unknown, accel::TracePath::best};
    std::vector<accel::Ray> sample;
    for (const std::size_t i : accel::policy_sample(a.offer(), r.count)) sample.push_back(ray_at(r, i));
    const accel::PathChoice choice = accel::choose_path(a.offer(), sample, req);
    race = accel::race_settles(choice, a.offer(), req) &&
           accel::race_chunk_count((r.count + ray_chunk - 1) / ray_chunk) != 0;
    req.path = choice.path;
    return req;
}

void check_rays(const RayArrays& r, const void* out, const char* fn) {
    if (r.count == 0) return;
    if (!r.origins || !r.directions)
        throw Error(Error::Kind::invalid_argument, std::string(fn) + ": " + (r.origins ? "directions" : "origins") + " is null");
    if (!out) throw Error(Error::Kind::invalid_argument, std::string(fn) + ": the output array is null");
}

/// Writes each ray's crossings into its row of `max_hits` records and its count.
class RowSink final : public accel::HitSink {
public:
    RowSink(const Scene::Impl& s, Hit* hits, std::int32_t* counts, std::size_t max_hits, std::size_t base)
        : s_(s), hits_(hits), counts_(counts), max_(max_hits), base_(base) {}
    void take(std::size_t i, std::span<accel::Hit> list) override {
        constexpr std::size_t most = 0x7FFFFFFF;
        counts_[base_ + i] = std::int32_t(std::min(list.size(), most));
        Hit* row = hits_ + (base_ + i) * max_;
        const std::size_t n = std::min(list.size(), max_);
        for (std::size_t k = 0; k < n; ++k) row[k] = s_.to_public(list[k]);
        for (std::size_t k = n; k < max_; ++k) row[k] = Hit{};
    }

private:
    const Scene::Impl& s_;
    Hit* hits_;
    std::int32_t* counts_;
    std::size_t max_, base_;
};

/// Traces `rays` for `q` with one path decision for the whole batch, in chunks over the call's
/// threads; `store(i, hit)` writes ray i's answer (intersect and occluded differ only there).
template <class Store>
void trace_batch(Scene::Impl& s, CallArena& arena, const RayArrays& rays, accel::Query q, Store&& store) {
    const accel::Accel& a = s.structure();
    bool race = false;
    const accel::TraceRequest req = batch_request(a, rays, q, race);
    const auto run = [&](std::size_t b, std::size_t e, const accel::TraceRequest& r, accel::ChunkPart part) {
        const auto in = load_rays(rays, b, e);
        thread_local std::vector<accel::Hit> out;
        out.resize(in.size());
        const std::size_t n = accel::trace_part(a, in, out, r, part);
        for (std::size_t i = b; i < e; ++i)
            if (accel::in_part(i - b, part)) store(i, out[i - b]);
        return n;
    };
    if (race) {
        const auto start = std::chrono::steady_clock::now();
        const std::size_t chunks = (rays.count + ray_chunk - 1) / ray_chunk;
        arena.execute([&] {
            accel::race_chunks(chunks, accel::race_chunk_count(chunks),
                               [&](std::size_t k, accel::TracePath path, accel::ChunkPart part) {
                                   accel::TraceRequest forced = req;
                                   forced.path = path;
                                   const std::size_t b = k * ray_chunk;
                                   return run(b, std::min(rays.count, b + ray_chunk), forced, part);
                               });
        });
        arena.answered(
            rays.count,
            std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start)
                              .count()));
        return;
    }
    for_chunks(arena, rays.count, ray_chunk,
               [&](std::size_t b, std::size_t e) { run(b, e, req, accel::ChunkPart::all); });
}

}  // namespace

void Scene::intersect(const RayArrays& rays, Hit* hits, const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "intersect");
        check_rays(rays, hits, "intersect");
        trace_batch(*impl_, arena, rays, accel::Query::closest,
                    [&](std::size_t i, const accel::Hit& h) { hits[i] = impl_->to_public(h); });
    });
}

void Scene::occluded(const RayArrays& rays, bool* occluded, const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "occluded");
        check_rays(rays, occluded, "occluded");
        trace_batch(*impl_, arena, rays, accel::Query::any,
                    [&](std::size_t i, const accel::Hit& h) { occluded[i] = h.is_hit(); });
    });
}

void Scene::intersect_all(const RayArrays& rays, std::size_t max_hits, Hit* hits, std::int32_t* counts,
                          const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "intersect_all");
        check_rays(rays, counts, "intersect_all");
        if (max_hits != 0 && rays.count != 0 && !hits)
            throw Error(Error::Kind::invalid_argument, "intersect_all: hits is null");
        const accel::Accel& a = impl_->structure();
        for_chunks(arena, rays.count, ray_chunk, [&](std::size_t b, std::size_t e) {
            RowSink sink(*impl_, hits, counts, max_hits, b);
            a.trace_all(load_rays(rays, b, e), sink);
        });
    });
}

void Scene::closest_point(const PointArrays& points, float max_distance, ClosestPoint* out,
                          const QueryOptions& options) const {
    PointValues reach;
    reach.value = max_distance;
    closest_point(points, reach, out, options);
}

void Scene::closest_point(const PointArrays& points, const PointValues& max_distance, ClosestPoint* out,
                          const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "closest_point");
        check_points(points, out, "closest_point");
        const auto reach = [&](std::size_t i) {
            return max_distance.values ? read_float(max_distance.values, max_distance.stride, i) : max_distance.value;
        };
        for (std::size_t i = 0; i < (max_distance.values ? points.count : 1); ++i)
            if (!(reach(i) >= 0.0f))
                throw Error(Error::Kind::invalid_argument,
                            "closest_point: max_distance" +
                                (max_distance.values ? "[" + std::to_string(i) + "]" : std::string()) +
                                " must be >= 0 (+inf: no limit), got " + std::to_string(reach(i)));
        const accel::Accel& a = impl_->structure();
        // Visited along a curve (api/point_order.h): the k-th point answered is point at(k).
        const std::vector<std::uint32_t> order = spatial_order(points, arena);
        const auto at = [&](std::size_t k) { return point_at(order, k); };
        for_chunks(arena, points.count, point_chunk, [&](std::size_t b, std::size_t e) {
            const auto in = load_points(points, order, b, e);
            thread_local std::vector<accel::PointHit> res;
            res.resize(e - b);
            // One call of the structure per run of points with the same reach (the whole chunk
            // when one distance is given for all).
            for (std::size_t i = b; i < e;) {
                const float r = reach(at(i));
                std::size_t j = i + 1;
                while (j < e && reach(at(j)) == r) ++j;
                a.closest_points(in.subspan(i - b, j - i), r, std::span(res).subspan(i - b, j - i));
                i = j;
            }
            for (std::size_t k = b; k < e; ++k) {
                const accel::PointHit& h = res[k - b];
                ClosestPoint& c = out[at(k)];
                c = ClosestPoint{};
                if (!h.is_hit()) continue;
                impl_->locate(h.prim, c.geom, c.prim, c.inst);
                c.distance = h.distance;
                c.point[0] = h.point.x, c.point[1] = h.point.y, c.point[2] = h.point.z;
                c.u = h.u, c.v = h.v;
            }
        });
    });
}

std::vector<Hit> Scene::intersect(const std::vector<Ray>& rays, const QueryOptions& options) const {
    std::vector<Hit> hits(rays.size());
    intersect(RayArrays::of(rays.data(), rays.size()), hits.data(), options);
    return hits;
}

std::vector<bool> Scene::occluded(const std::vector<Ray>& rays, const QueryOptions& options) const {
    const std::unique_ptr<bool[]> out(new bool[rays.size()]);
    occluded(RayArrays::of(rays.data(), rays.size()), out.get(), options);
    return std::vector<bool>(out.get(), out.get() + rays.size());
}

std::vector<ClosestPoint> Scene::closest_point(const std::vector<float>& xyz, float max_distance,
                                               const QueryOptions& options) const {
    const PointArrays p = packed_points(xyz, "closest_point");
    std::vector<ClosestPoint> out(p.count);
    closest_point(p, max_distance, out.data(), options);
    return out;
}

}  // namespace arbor
