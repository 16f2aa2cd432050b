#pragma once
/// The batch plumbing of arbor::Scene's point queries (closest point, inside, winding numbers,
/// signed distances): chunks with fixed boundaries over the scene's threads, so that answers do
/// not depend on the thread count, the caller's strided points read into a per-thread buffer, and
/// the argument checks every point query makes.
#include "api/scene_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace arbor {

/// Points per chunk of a point query.
inline constexpr std::size_t point_chunk = 256;

/// Calls f(begin, end) for the chunks [k * chunk, (k + 1) * chunk) of [0, n), in parallel on the
/// scene's threads.
template <class F>
void for_chunks(const Scene::Impl& s, std::size_t n, std::size_t chunk, F&& f) {
    if (n == 0) return;
    s.arena->execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (n + chunk - 1) / chunk, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t k = r.begin(); k != r.end(); ++k)
                                  f(k * chunk, std::min(n, (k + 1) * chunk));
                          });
    });
}

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
