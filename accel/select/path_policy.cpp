#include "accel/select/path_policy.h"

#include "accel/accel.h"
#include "accel/bvh/bvh_accel.h"
#include "accel/select/coherence.h"

#include <cmath>
#include <cstdio>

namespace arbor::accel {

namespace {
/// Groups of a batch whose origins lie within this fraction of the scene's diagonal start together.
constexpr float together_fraction = 0.05f;
/// Packets when at least this fraction of the groups is coherent.
constexpr double packet_fraction = 0.5;

PathChoice choose_offered(const PathOffer& offer, std::span<const Ray> rays, const TraceRequest& req) {
    const Query q = req.query;
    PathChoice c;
    if (req.calibrated != TracePath::best && offer.runs(req.calibrated, q)) {
        c.path = req.calibrated, c.why = PathChoice::Why::calibrated;
        return c;
    }
    const bool packet = offer.runs(TracePath::packet, q), single = offer.runs(TracePath::single, q);
    if (!packet && !single) {
        c.path = TracePath::scalar;
        c.why = offer.simd_skipped ? PathChoice::Why::only_scalar_built : PathChoice::Why::only_path;
        return c;
    }
    if (!packet || !single) {
        c.path = packet ? TracePath::packet : TracePath::single, c.why = PathChoice::Why::only_path;
        return c;
    }
    if (!offer.packets_pay) {
        c.path = TracePath::single, c.why = PathChoice::Why::packets_do_not_pay;
        return c;
    }
    if (req.hint != RayHint::unknown) {
        c.path = req.hint == RayHint::coherent ? TracePath::packet : TracePath::single;
        c.why = PathChoice::Why::hint, c.hint = req.hint;
        return c;
    }
    // Packets for groups that share an octant and a place (primary, shadow rays) and for groups
    // that share a place only (diffuse bounces: their packets switch to single rays early, see
    // PacketConfig::switch_mixed); single rays for scattered origins.
    const float spread = together_fraction * offer.scene_diagonal;
    c.why = PathChoice::Why::measured;
    c.group = offer.packet_lanes;
    c.coherent = coherent_fraction(rays, offer.packet_lanes, spread);
    c.one_octant = c.coherent >= packet_fraction;
    c.together = c.one_octant ? c.coherent : coherent_fraction(rays, offer.packet_lanes, spread, 8, false);
    c.path = c.together >= packet_fraction ? TracePath::packet : TracePath::single;
    // Any-hit rays that share an octant wherever they start (shadow rays towards one light from a
    // view whose tile neighbours lie far apart on the model): the packet path, whose intervals
    // cull the nodes around the shared target. Chosen on the benchmark's shadow files (packet at or
    // above best on 8 of the 9 BVH cells of perf/results/vs-embree-2026-12-02f.md), not on the
    // held-out set it is reported on.
    if (c.path == TracePath::single && q == Query::any) {
        c.octant_only = coherent_fraction(rays, offer.packet_lanes, INFINITY);
        if (c.octant_only >= packet_fraction) c.path = TracePath::packet;
    }
    return c;
}
}  // namespace

std::vector<std::size_t> policy_sample(const PathOffer& offer, std::size_t n) {
    const std::size_t group = std::max<std::size_t>(offer.packet_lanes, 1), step = coherence_sample_step(n, group);
    std::vector<std::size_t> at;
    for (std::size_t base = 0; base < n; base += step)
        for (std::size_t i = base; i < std::min(n, base + group); ++i) at.push_back(i);
    return at;
}

PathChoice choose_path(const PathOffer& offer, std::span<const Ray> rays, const TraceRequest& req) {
    if (req.path != TracePath::best && offer.runs(req.path, req.query)) {
        PathChoice c;
        c.path = req.path, c.why = PathChoice::Why::forced;
        return c;
    }
    PathChoice c = choose_offered(offer, rays, req);
    c.not_offered = req.path;
    return c;
}

std::string path_reason(const PathChoice& c) {
    std::string why;
    switch (c.why) {
    case PathChoice::Why::forced: return "forced with --path";
    case PathChoice::Why::calibrated: why = "auto's pick (auto_reason says why)"; break;
    case PathChoice::Why::only_path: why = "the only path of this structure"; break;
    case PathChoice::Why::only_scalar_built: why = "only the scalar layout was built"; break;
    case PathChoice::Why::packets_do_not_pay:
        why = "this structure's packet path is slower than its single path on every kind of ray (measured)";
        break;
    case PathChoice::Why::hint:
        why = c.hint == RayHint::coherent ? "coherent rays (a tile's camera or shadow rays): packets"
                                          : "incoherent rays (bounces): single rays";
        break;
    case PathChoice::Why::measured: {
        char buf[200];
        if (c.one_octant)
            std::snprintf(buf, sizeof buf, "%.0f%% of the %u-ray groups are coherent (one octant, origins within 5%% of the scene)",
                          100.0 * c.coherent, unsigned(c.group));
        else
            std::snprintf(buf, sizeof buf,
                          "%.0f%% of the %u-ray groups are coherent (one octant, origins within 5%% of the scene), %.0f%% start "
                          "together (origins within 5%%)",
                          100.0 * c.coherent, unsigned(c.group), 100.0 * c.together);
        why = buf;
        if (c.octant_only >= packet_fraction) {
            std::snprintf(buf, sizeof buf, "; any-hit rays, %.0f%% of the groups in one octant: packets", 100.0 * c.octant_only);
            why += buf;
        }
        break;
    }
    }
    if (c.not_offered != TracePath::best)
        return "no " + std::string(to_string(c.not_offered)) + " path here, took best: " + why;
    return why;
}

PathOffer expected_offer(AccelKind kind, const BuildConfig& cfg) {
    PathOffer o;
    const bool simd = cfg.layouts != Layouts::scalar, scalar = cfg.layouts != Layouts::simd;
    switch (kind) {
    case AccelKind::brute:
        o.add(TracePath::scalar), o.counts = true;
        break;
    case AccelKind::bvh_median:
    case AccelKind::bvh_sah:
    case AccelKind::lbvh:
        if (scalar) o.add(TracePath::scalar);
        o.counts = scalar, o.simd_skipped = !simd;
        if (simd) o.add(TracePath::single), o.add(TracePath::packet), o.packets_pay = true;
        break;
    case AccelKind::kdtree:  // the scalar path reads the tree itself, which every build makes
        o.add(TracePath::scalar), o.counts = true, o.simd_skipped = !simd;
        if (simd) o.add(TracePath::single), o.add(TracePath::packet);
        break;
    default: break;
    }
    return o;
}

Layouts layouts_for(TracePath path) { return path == TracePath::scalar ? Layouts::scalar : Layouts::simd; }

std::vector<std::string> skipped_by_build(AccelKind kind, const BuildConfig& cfg) {
    std::vector<std::string> out;
    if (kind == AccelKind::brute) return out;  // no layouts
    if (cfg.layouts == Layouts::scalar) out.push_back("SIMD layouts (only the SIMD paths read them)");
    const bool bvh = kind == AccelKind::bvh_median || kind == AccelKind::bvh_sah || kind == AccelKind::lbvh;
    // (The kd-tree's scalar path reads the tree itself, which every build makes.)
    if (cfg.layouts == Layouts::simd && bvh) out.push_back("scalar layout (only the scalar path reads it)");
    // A BVH built for the SIMD paths only stops splitting at the layout's width (bvh_leaf_floor).
    const std::uint32_t floor = bvh ? bvh_leaf_floor(cfg) : 0;
    if (floor > 1)
        out.push_back("binary splits of ranges of at most " + std::to_string(floor) +
                      " triangles (the SIMD leaves' blocks hold them; --simd-leaf-floor 1 makes them)");
    return out;
}

}  // namespace arbor::accel
