#pragma once
/// The Embree peer's view of Embree's ray queries, the same under Embree 3 and Embree 4: the header
/// of the major version perf/CMakeLists.txt found (ARBOR_EMBREE_MAJOR), one per-call context built
/// from the coherent flag, and rtcIntersect/rtcOccluded for 1, 8 and 16 rays taking that context.
/// Embree 4 replaced Embree 3's RTCIntersectContext (rtcInitIntersectContext, passed before the
/// rays) by RTCIntersectArguments and RTCOccludedArguments (rtcInitIntersectArguments and
/// rtcInitOccludedArguments, passed after the rays), and removed the stream calls
/// rtcIntersect1M/rtcOccluded1M: ARBOR_EMBREE_STREAM says whether they exist. Everything else the
/// peer calls (devices, scenes, buffers, instances, RTCRay/RTCRayHit and their packets) is the same.
/// Included only by perf/embree_peer.cpp.
#if ARBOR_EMBREE_MAJOR == 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

#ifdef ARBOR_EMBREE_MAJOR
static_assert(RTC_VERSION_MAJOR == ARBOR_EMBREE_MAJOR, "the Embree header is not of the major version CMake found");
#endif

namespace arbor::perf::embree_api {

#if RTC_VERSION_MAJOR >= 4

#define ARBOR_EMBREE_STREAM 0

/// Embree 4's arguments of one closest-hit and one any-hit query, default but for the coherent flag.
struct Context {
    RTCIntersectArguments closest;
    RTCOccludedArguments any;
    explicit Context(bool coherent) {
        rtcInitIntersectArguments(&closest);
        rtcInitOccludedArguments(&any);
        if (coherent) closest.flags = any.flags = RTC_RAY_QUERY_FLAG_COHERENT;
    }
};

inline void intersect(RTCScene s, Context& c, RTCRayHit* rh) { rtcIntersect1(s, rh, &c.closest); }
inline void occluded(RTCScene s, Context& c, RTCRay* r) { rtcOccluded1(s, r, &c.any); }
inline void intersect(const int* valid, RTCScene s, Context& c, RTCRayHit8* rh) {
    rtcIntersect8(valid, s, rh, &c.closest);
}
inline void occluded(const int* valid, RTCScene s, Context& c, RTCRay8* r) { rtcOccluded8(valid, s, r, &c.any); }
inline void intersect(const int* valid, RTCScene s, Context& c, RTCRayHit16* rh) {
    rtcIntersect16(valid, s, rh, &c.closest);
}
inline void occluded(const int* valid, RTCScene s, Context& c, RTCRay16* r) { rtcOccluded16(valid, s, r, &c.any); }

#else

#define ARBOR_EMBREE_STREAM 1

/// Embree 3's intersect context, default but for the coherent flag.
struct Context {
    RTCIntersectContext ctx;
    explicit Context(bool coherent) {
        rtcInitIntersectContext(&ctx);
        if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    }
};

inline void intersect(RTCScene s, Context& c, RTCRayHit* rh) { rtcIntersect1(s, &c.ctx, rh); }
inline void occluded(RTCScene s, Context& c, RTCRay* r) { rtcOccluded1(s, &c.ctx, r); }
inline void intersect(const int* valid, RTCScene s, Context& c, RTCRayHit8* rh) { rtcIntersect8(valid, s, &c.ctx, rh); }
inline void occluded(const int* valid, RTCScene s, Context& c, RTCRay8* r) { rtcOccluded8(valid, s, &c.ctx, r); }
inline void intersect(const int* valid, RTCScene s, Context& c, RTCRayHit16* rh) {
    rtcIntersect16(valid, s, &c.ctx, rh);
}
inline void occluded(const int* valid, RTCScene s, Context& c, RTCRay16* r) { rtcOccluded16(valid, s, &c.ctx, r); }
/// The stream calls on n consecutive rays.
inline void intersect_stream(RTCScene s, Context& c, RTCRayHit* rh, unsigned n) {
    rtcIntersect1M(s, &c.ctx, rh, n, sizeof(RTCRayHit));
}
inline void occluded_stream(RTCScene s, Context& c, RTCRay* r, unsigned n) {
    rtcOccluded1M(s, &c.ctx, r, n, sizeof(RTCRay));
}

#endif

}  // namespace arbor::perf::embree_api
