#pragma once
/// How a batch call runs: over chunks with fixed boundaries (so the answers do not depend on the
/// thread count), in parallel, in the scene's task arena or in one of the threads the call's
/// QueryOptions ask for; and the point queries' shared plumbing (closest point, inside, winding
/// numbers, signed distances): the caller's strided points read into a per-thread buffer, and the
/// argument checks every point query makes.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "api/scene_impl.h"

namespace arbor {

/// The arena of one call: the scene's when options.threads is 0 or the scene's own count, else
/// its own arena of that many threads (capped at the cores). Throws Error(invalid_argument),
/// naming `fn`, for a negative count.
class CallArena {
public:
    CallArena(const Scene::Impl& s, const QueryOptions& o, const char* fn) : s_(s) {
        if (o.threads < 0)
            throw Error(Error::Kind::invalid_argument,
                        std::string(fn) + ": threads must be >= 0 (0 = the scene's), got " + std::to_string(o.threads));
        threads_ = usable_threads(o.threads);
    }

    /// Counts `n` rays or points answered in `ns` nanoseconds, for update_vertices' decision.
    void answered(std::size_t n, std::uint64_t ns) const {
        s_.answered.fetch_add(n, std::memory_order_relaxed);
        s_.answer_ns.fetch_add(ns, std::memory_order_relaxed);
    }

    /// Runs f() in the arena (a scene never built has no arena yet: then one of the call's own).
    template <class F>
    void execute(F&& f) {
        if (s_.arena && (threads_ == 0 || threads_ == s_.threads)) return s_.arena->execute(std::forward<F>(f));
        if (!own_) own_.emplace(threads_ > 0 ? threads_ : int(tbb::task_arena::automatic));
        own_->execute(std::forward<F>(f));
    }

private:
    const Scene::Impl& s_;
    int threads_ = 0;
    std::optional<tbb::task_arena> own_;
};

/// Calls f(begin, end) for the chunks [k * chunk, (k + 1) * chunk) of [0, n), in parallel in `arena`,
/// and, when `counted` (queries; not hit_normals, which walks no tree), counts the n answers and
/// their wall time (CallArena::answered).
template <class F>
void for_chunks(CallArena& arena, std::size_t n, std::size_t chunk, F&& f, bool counted = true) {
    if (n == 0) return;
    const auto start = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (n + chunk - 1) / chunk, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t k = r.begin(); k != r.end(); ++k)
                                  f(k * chunk, std::min(n, (k + 1) * chunk));
                          });
    });
    if (counted)
        arena.answered(n, std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now() - start).count()));
}

/// Points per chunk of a point query.
inline constexpr std::size_t point_chunk = 256;

inline accel::Vec3f read_vec3(const float* base, std::size_t stride, std::size_t i) {
    float v[3];
    std::memcpy(v, reinterpret_cast<const unsigned char*>(base) + i * stride, sizeof v);
    return {v[0], v[1], v[2]};
}

/// Points begin .. end - 1 in this thread's buffer.
inline std::span<const accel::Vec3f> load_points(const PointArrays& p, std::size_t begin, std::size_t end) {
    thread_local std::vector<accel::Vec3f> buf;
    buf.resize(end - begin);
    for (std::size_t i = begin; i < end; ++i) buf[i - begin] = read_vec3(p.xyz, p.stride, i);
    return buf;
}

/// Error(invalid_argument) naming `fn` for a null points or output array (with points to answer).
inline void check_points(const PointArrays& p, const void* out, const char* fn) {
    if (p.count == 0) return;
    if (!p.xyz) throw Error(Error::Kind::invalid_argument, std::string(fn) + ": points is null");
    if (!out) throw Error(Error::Kind::invalid_argument, std::string(fn) + ": the output array is null");
}

/// Packed x, y, z triples as PointArrays; Error(invalid_argument) naming `fn` for a size that is not
/// a multiple of 3.
inline PointArrays packed_points(const std::vector<float>& xyz, const char* fn) {
    if (xyz.size() % 3 != 0)
        throw Error(Error::Kind::invalid_argument,
                    std::string(fn) + ": points must hold x, y, z triples (size " + std::to_string(xyz.size()) + ")");
    return {xyz.size() / 3, xyz.data(), 3 * sizeof(float)};
}

}  // namespace arbor
