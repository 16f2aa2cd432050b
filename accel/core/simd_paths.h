#pragma once
/// SimdPaths<D>: the dispatch shared by the SIMD paths of every structure (the BVHs' wide layouts,
/// wide/wide_paths_impl.h, and the kd-tree's SIMD blocks, kdtree/kdtree_simd.cpp): the query
/// becomes a compile-time AnyHit, the path `packet` or `single`, the packet width a lane type. The
/// structure D supplies
///   template <bool AnyHit> void trace_single(rays, hits) const;
///   template <bool AnyHit, class P> void trace_packets(rays, hits) const;   // P = Float8 or Float16
/// and the settings of its packets are resolved here once, from BuildConfig.
#include "accel/core/build_config.h"
#include "accel/core/query.h"
#include "accel/core/ray.h"

#include <span>

namespace arbor::accel {

/// The packet path's settings, as a build resolves them (0 and -1 in BuildConfig: the defaults).
struct PacketSettings {
    std::uint32_t lanes = 8;  ///< rays per packet: 8, or 16 with AVX-512
    int switch_lanes = 1;     ///< at a node (kd-tree: leaf) reached by at most this many lanes they go on alone
    int switch_mixed = 4;     ///< the same for packets whose lanes do not share one direction octant (BVHs)
};

/// cfg's packet settings with the defaults filled in: lanes cfg.packet_lanes when 8 or 16 and this
/// build has them (else 16 with AVX-512, 8 otherwise), switch_lanes lanes / 8, switch_mixed lanes / 2.
inline PacketSettings resolve_packets(const BuildConfig& cfg) {
    PacketSettings s;
    constexpr bool has16 = XSIMD_WITH_AVX512F != 0;
    s.lanes = cfg.packet_lanes == 8 || cfg.packet_lanes == 16 ? cfg.packet_lanes : (has16 ? 16 : 8);
    if (!has16) s.lanes = 8;
    s.switch_lanes = cfg.packet_switch >= 0 ? cfg.packet_switch : int(s.lanes / 8);
    s.switch_mixed = cfg.packet_switch_mixed >= 0 ? cfg.packet_switch_mixed : int(s.lanes / 2);
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
            if (any) d.template trace_packets<true, simd::Float8>(rays, hits);
            else d.template trace_packets<false, simd::Float8>(rays, hits);
            return;
        }
        if (any) d.template trace_single<true>(rays, hits);
        else d.template trace_single<false>(rays, hits);
    }

    PacketSettings packets_;
};

}  // namespace arbor::accel
