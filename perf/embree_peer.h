#pragma once
/// The Embree peer: Embree 3 or 4 fed the very same triangles and rays as arbor, in the same
/// process, on the same threads, so the benchmark can print ratios. Built only when
/// find_package(embree ARBOR_EMBREE_MAJOR) succeeds and ARBOR_EMBREE is ON (ARBOR_HAVE_EMBREE is
/// then defined; Embree 3 by default, Embree 4 built by scripts/peers/build_embree4.sh); arbor's
/// libraries never link Embree. Embree's answers are converted to accel::Hit: prim = primID, and (u, v) are
/// Embree's barycentrics, which weight v1 and v2 exactly as spec/rayfile.md's u, v do (checked by
/// tests/test_embree_peer.cpp). Any-hit answers carry t = tnear and prim = 0 (Embree reports only
/// "occluded"): compare them by is_hit().
///
/// Embree's default triangle test is not watertight, and even RTC_SCENE_FLAG_ROBUST is reported
/// to miss some edge hits (embree#387): the benchmark counts the disagreements, it does not hide them.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "accel/instances/affine.h"
#include "accel/interface/trace.h"

namespace arbor::perf {

/// How rays are handed to Embree: rtcIntersect1/rtcOccluded1 per ray, 8- or 16-wide packets
/// (rtcIntersect8/16 with a valid mask), or the stream call rtcIntersect1M/rtcOccluded1M, which
/// only Embree 3 has (Embree 4 removed the stream calls).
enum class EmbreeCall { single, packet8, packet16, stream };
std::string_view to_string(EmbreeCall c);
/// The calls the linked Embree has, in the order above: 1, 8, 16 and, under Embree 3 only, 1M.
/// Benchmarks time these and no others, so a call Embree lacks is absent from their reports.
std::span<const EmbreeCall> embree_calls();
/// Whether `c` is one of embree_calls().
bool embree_has(EmbreeCall c);

struct EmbreeConfig {
    /// RTC_BUILD_QUALITY_HIGH (spatial splits) instead of MEDIUM, Embree's default.
    bool high_quality = false;
    /// RTC_SCENE_FLAG_ROBUST: robust traversal, no accuracy-reducing optimizations. Off by default
    /// in Embree, and then its triangle test is not watertight.
    bool robust = false;
    /// Copy the index buffer into an Embree-owned buffer instead of sharing the view's indices.
    /// (Vertices are always copied: Embree wants xyz records, the view holds separate x, y, z arrays.)
    bool copy_indices = false;
};
/// "embree", "embree-high", "embree-robust", "embree-high-robust" (plus "-copy").
std::string embree_config_name(const EmbreeConfig& cfg);

class EmbreePeer {
public:
    /// Builds the Embree scene over `tris` (the view must outlive the peer unless copy_indices)
    /// and commits it; build_ms() is the time of rtcCommitScene. Throws std::runtime_error with
    /// Embree's error message when Embree fails.
    EmbreePeer(const accel::TriangleView& tris, const EmbreeConfig& cfg = {});
    /// Embree's two-level scene: `mesh` in a scene of its own, placed once per transform by an
    /// RTC_GEOMETRY_TYPE_INSTANCE (rtcSetGeometryTransform, 3x4 row-major, rounded to float) in the
    /// top scene. Hits carry arbor's global triangle numbers (instance k's triangle j is
    /// k * triangle count + j, as accel::InstanceAccel numbers them); build_ms() is both commits.
    EmbreePeer(const accel::TriangleView& mesh, std::span<const accel::Affine> placements,
               const EmbreeConfig& cfg = {});
    ~EmbreePeer();
    EmbreePeer(const EmbreePeer&) = delete;
    EmbreePeer& operator=(const EmbreePeer&) = delete;

    const EmbreeConfig& config() const;
    /// Wall time of rtcCommitScene (the BVH build), in ms.
    double build_ms() const;
    /// Wall time of device, geometry and buffer setup before the commit, in ms.
    double setup_ms() const;
    /// Bytes Embree allocated during the commit (its acceleration structure), from the device's
    /// memory monitor.
    std::size_t memory_bytes() const;
    /// Triangles of the scene's mesh (once, however often it is placed).
    std::size_t triangles() const;

    /// Traces rays[i] into hits[i] on the calling thread. `coherent` sets the coherent flag (rays
    /// from one image tile: Embree 3's RTC_INTERSECT_CONTEXT_FLAG_COHERENT, Embree 4's
    /// RTC_RAY_QUERY_FLAG_COHERENT). Rays that arbor would not trace (accel::ray_is_traceable) are
    /// handed to Embree as inactive and come back as misses. Throws std::invalid_argument for a call
    /// the linked Embree does not have (embree_has).
    void trace(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, accel::Query query, EmbreeCall call,
               bool coherent) const;
    /// The same in parallel over chunks of `chunk` rays, exactly as accel::trace_parallel does.
    void trace_parallel(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, accel::Query query,
                        EmbreeCall call, bool coherent, std::size_t chunk = 1024) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// One line about the Embree library in use: version (e.g. "Embree 4.4.1"), native packet widths,
/// stream support (none in Embree 4), tasking.
std::string embree_description();

}  // namespace arbor::perf
