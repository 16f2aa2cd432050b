#pragma once
/// SimdPaths<D>: the dispatch shared by the SIMD paths of every structure (the BVHs' wide layouts,
/// structures/wide_paths_impl.h, and the kd-tree's SIMD blocks, structures/kdtree_simd.cpp): the query
/// becomes a compile-time AnyHit, the path `packet` or `single`, the packet width a lane type. The
/// structure D supplies
///   template <bool AnyHit> void trace_single(rays, hits) const;
///   template <bool AnyHit, class P> void trace_packets(rays, hits) const;   // P = Float4, Float8 or Float16
/// and the settings of its packets (PacketConfig, BuildConfig::packets) are resolved here once.
#include "accel/core/query.h"
#include "accel/core/ray.h"

#include <algorithm>
#include <span>

namespace arbor::accel {

/// The packet path's settings as asked (BuildConfig::packets; 0 and -1: the defaults), read by
/// resolve_packets below and nowhere else.
struct PacketConfig {
    /// Rays per packet, 8 or 16 (0, or more than the kernel set has: its widest, 16 with AVX-512,
    /// 8 with AVX2, 4 with SSE4.2).
    std::uint32_t lanes = 0;
    /// BVHs: at a node reached by at most this many lanes they go on as single rays (kd-tree: a
    /// leaf reached by at most this many lanes is tested lane by lane) (-1 = lanes / 8).
    int switch_lanes = -1;
    /// BVHs: the same for packets whose lanes do not all share a direction octant (diffuse
    /// bounces: such packets part ways within a level or two; 1.05-1.15x over lanes / 8)
    /// (-1 = lanes / 2).
    int switch_mixed = -1;
};

/// The packet path's settings, as a build resolves them.
struct PacketSettings {
    std::uint32_t lanes = 8;  ///< rays per packet: 8, or 16 with AVX-512, 4 with SSE4.2 only
    int switch_lanes = 1;     ///< at a node (kd-tree: leaf) reached by at most this many lanes they go on alone
    int switch_mixed = 4;     ///< the same for packets whose lanes do not share one direction octant (BVHs)
};

/// cfg with the defaults filled in: lanes cfg.lanes when 8 or 16 and this kernel set has them
/// (else its widest: 16 with AVX-512, 8 with AVX2, 4 with SSE4.2), switch_lanes lanes / 8 (at
/// least 1), switch_mixed lanes / 2. Called only by the kernel set's own code (the structures'
/// SIMD paths), whose compile flags decide the XSIMD_WITH_* macros.
inline PacketSettings resolve_packets(const PacketConfig& cfg) {
    PacketSettings s;
    constexpr std::uint32_t widest = XSIMD_WITH_AVX512F ? 16 : (XSIMD_WITH_AVX2 ? 8 : 4);
    s.lanes = (cfg.lanes == 8 || cfg.lanes == 16) && cfg.lanes <= widest ? cfg.lanes : widest;
    s.switch_lanes = cfg.switch_lanes >= 0 ? cfg.switch_lanes : std::max(1, int(s.lanes / 8));
    s.switch_mixed = cfg.switch_mixed >= 0 ? cfg.switch_mixed : int(s.lanes / 2);
    return s;
}

template <class D> class SimdPaths {
public:
    const PacketSettings& packets() const { return packets_; }

protected:
    explicit SimdPaths(const PacketSettings& packets) : packets_(packets) {}

    /// rays on `path` (packet; anything else: single) for `query`.
    void trace_simd(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path) const {
        const D& d = static_cast<const D&>(*this);
        const bool any = query == Query::any;
        if (path == TracePath::packet) {
#if XSIMD_WITH_AVX512F
            if (packets_.lanes == 16) {
                if (any) d.template trace_packets<true, simd::Float16>(rays, hits);
                else d.template trace_packets<false, simd::Float16>(rays, hits);
                return;
            }
#endif
#if XSIMD_WITH_AVX2
            if (any) d.template trace_packets<true, simd::Float8>(rays, hits);
            else d.template trace_packets<false, simd::Float8>(rays, hits);
#else
            // SSE4.2 only (the portable build's sse4 kernel set): packets of 4 lanes.
            if (any) d.template trace_packets<true, simd::Float4>(rays, hits);
            else d.template trace_packets<false, simd::Float4>(rays, hits);
#endif
            return;
        }
        if (any) d.template trace_single<true>(rays, hits);
        else d.template trace_single<false>(rays, hits);
    }

    PacketSettings packets_;
};

}  // namespace arbor::accel
