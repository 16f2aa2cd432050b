#include "accel/interface/path_policy.h"

#include "accel/interface/accel.h"
#include "accel/interface/coherence.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace arbor::accel {

namespace {
/// Groups of a batch whose origins lie within this fraction of the scene's diagonal start together.
constexpr float together_fraction = 0.05f;
/// Packets when at least this fraction of the groups is coherent.
constexpr double packet_fraction = 0.5;

/// The policy's four measures of a batch, over the same sample as coherent_fraction (coherence.h:
/// at most 8 groups of `group` consecutive rays, spread evenly; groups without traceable rays do
/// not count), each the fraction of groups whose traceable rays
///   coherent:     share a direction octant and start within `spread` of each other (every axis);
///   together:     start within `spread`;
///   octant:       share a direction octant;
///   end_together: END within `spread` (org + tfar * dir; a ray whose end is not finite makes its
///                 group scattered): shadow rays towards one point light, tfar just short of it,
///                 end together wherever they start and in whatever octants.
/// One pass over the sample, instead of up to three coherent_fraction calls.
struct BatchMeasures {
    double coherent = 0.0, together = 0.0, octant = 0.0, end_together = 0.0;
};

/// What one sampled group's traceable rays have in common: whether there are any, the sign bits of
/// d set in all of them / in some, the box of their origins and of their ends (org + tfar * dir),
/// and whether every end is finite.
struct GroupMeasure {
    bool any = false, ends_finite = true;
    unsigned neg_all = 7, neg_any = 0;
    Vec3f lo{INFINITY}, hi{-INFINITY}, elo{INFINITY}, ehi{-INFINITY};
};

/// The measure of rays [base, end), one ray at a time (any group size, any build).
GroupMeasure measure_group(std::span<const Ray> rays, std::size_t base, std::size_t end) {
    GroupMeasure g;
    for (std::size_t i = base; i < end; ++i) {
        const Ray& r = rays[i];
        if (!ray_is_traceable(r)) continue;
        const unsigned o = unsigned(std::signbit(r.dir.x)) | unsigned(std::signbit(r.dir.y)) << 1 |
                           unsigned(std::signbit(r.dir.z)) << 2;
        g.neg_all &= o, g.neg_any |= o;
        const Vec3f e = r.org + r.tfar * r.dir;  // inf or NaN where tfar is not finite
        g.ends_finite = g.ends_finite && std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z);
        g.any = true;
        g.lo = simd::vmin(r.org, g.lo), g.hi = simd::vmax(r.org, g.hi);
        g.elo = simd::vmin(e, g.elo), g.ehi = simd::vmax(e, g.ehi);
    }
    return g;
}

#if defined(__AVX512F__) && defined(__AVX512DQ__)
/// The same for 16 consecutive rays, two 32-byte records {org, tnear, dir, tfar} per 512-bit
/// register: the traceable rule (simd/ray.h) as lane masks, the boxes as lane-wise minima and
/// maxima over the rows (exact, so in any order the same as one ray at a time: min and max of
/// finite floats do not round, and a non-finite end is caught by its own test, not by the
/// box). A scalar loop took ~7% of the packet path's time on fast shadow cells (alligator,
/// 1024-ray chunks, 8 groups of 16 looked at per chunk).
GroupMeasure measure_group16(const Ray* rays) {
    static_assert(sizeof(Ray) == 32 && offsetof(Ray, tnear) == 12 && offsetof(Ray, dir) == 16 && offsetof(Ray, tfar) == 28);
    const __m512 inf = _mm512_set1_ps(INFINITY), ninf = _mm512_set1_ps(-INFINITY);
    const __m512 min_normal = _mm512_set1_ps(std::numeric_limits<float>::min());
    // Per lane of a row: its ray's direction (origin lanes 0-2 / 8-10 from lanes 4-6 / 12-14) and tfar
    // (from lane 7 / 15), and tfar beside tnear (lane 3 / 11).
    const __m512i dir_idx = _mm512_setr_epi32(4, 5, 6, 7, 4, 5, 6, 7, 12, 13, 14, 15, 12, 13, 14, 15);
    const __m512i tfar_idx = _mm512_setr_epi32(7, 7, 7, 7, 7, 7, 7, 7, 15, 15, 15, 15, 15, 15, 15, 15);
    constexpr __mmask16 org_lanes = 0x0707, dir_lanes = 0x7070;
    __m512 lo = inf, hi = ninf, elo = inf, ehi = ninf;
    GroupMeasure g;
    bool ends_finite = true;
    for (int row = 0; row < 8; ++row) {
        const __m512 v = _mm512_loadu_ps(reinterpret_cast<const float*>(rays + 2 * row));
        // Not finite (NaN or +-inf: fpclass 0x01 | 0x80 | 0x08 | 0x10) among org and dir; some |d[k]| >= FLT_MIN;
        // tnear <= tfar (false for NaN).
        const unsigned bad = unsigned(_mm512_fpclass_ps_mask(v, 0x99)) & (org_lanes | dir_lanes);
        const unsigned big = unsigned(_mm512_cmp_ps_mask(_mm512_abs_ps(v), min_normal, _CMP_GE_OQ)) & dir_lanes;
        const __m512 tf = _mm512_maskz_permutexvar_ps(0xffff, tfar_idx, v);
        const unsigned ordered = unsigned(_mm512_cmp_ps_mask(v, tf, _CMP_LE_OQ));
        unsigned rows = 0;  // lanes of the traceable rays of this row: 0x00ff, 0xff00
        for (int h = 0; h < 2; ++h) {
            const unsigned sh = 8u * unsigned(h);
            if (((bad >> sh) & 0x77u) == 0 && ((big >> sh) & 0x70u) != 0 && ((ordered >> (sh + 3)) & 1u) != 0) {
                rows |= 0xffu << sh;
                const unsigned o = (unsigned(_mm512_movepi32_mask(_mm512_castps_si512(v))) >> (sh + 4)) & 7u;
                g.neg_all &= o, g.neg_any |= o;
            }
        }
        if (rows == 0) continue;
        g.any = true;
        const __mmask16 k = __mmask16(rows);
        lo = _mm512_mask_min_ps(lo, k, v, lo), hi = _mm512_mask_max_ps(hi, k, v, hi);
        // End = org + tfar * dir, rounded as the scalar Vec3 expression (two roundings, no fma).
        const __m512 e = _mm512_add_ps(v, _mm512_mul_ps(tf, _mm512_maskz_permutexvar_ps(0xffff, dir_idx, v)));
        ends_finite = ends_finite && (unsigned(_mm512_fpclass_ps_mask(e, 0x99)) & org_lanes & rows) == 0;
        elo = _mm512_mask_min_ps(elo, k, e, elo), ehi = _mm512_mask_max_ps(ehi, k, e, ehi);
    }
    // Lanes 0-2 (first ray of each row) and 8-10 (second) together.
    const auto fold = [](__m512 x, bool low) {
        alignas(64) float f[16];
        _mm512_store_ps(f, x);
        Vec3f r;
        for (int k = 0; k < 3; ++k) r[k] = low ? simd::rmin(f[k], f[8 + k]) : simd::rmax(f[k], f[8 + k]);
        return r;
    };
    g.ends_finite = ends_finite;
    g.lo = fold(lo, true), g.hi = fold(hi, false), g.elo = fold(elo, true), g.ehi = fold(ehi, false);
    return g;
}
#endif

BatchMeasures measure_batch(std::span<const Ray> rays, std::size_t group, float spread, std::size_t max_groups = 8) {
    group = std::max<std::size_t>(group, 1);
    // The sample's groups start a step apart (policy_sample gathers the same rays).
    const std::size_t step = coherence_sample_step(rays.size(), group, max_groups);
    std::size_t groups = 0, coherent = 0, together = 0, octant = 0, end_together = 0;
    // The sampled groups lie a stride apart (4 KiB in a 1024-ray chunk) in rays the trace has not
    // read yet: loaded one after another they miss the cache in turn (the measure took 14% of the
    // packet path's time on the alligator's shadow rays, perf record); asked for all at once first,
    // the misses overlap.
    for (std::size_t base = 0; base < rays.size(); base += step) {
        const char* p = reinterpret_cast<const char*>(rays.data() + base);
        const char* e = reinterpret_cast<const char*>(rays.data() + std::min(rays.size(), base + group));
        for (; p < e; p += 64) __builtin_prefetch(p);
    }
    const auto within = [spread](const Vec3f& l, const Vec3f& h) {
        return h.x - l.x <= spread && h.y - l.y <= spread && h.z - l.z <= spread;
    };
    for (std::size_t base = 0; base < rays.size(); base += step) {
        const std::size_t end = std::min(rays.size(), base + group);
#if defined(__AVX512F__) && defined(__AVX512DQ__)
        const GroupMeasure g = end - base == 16 ? measure_group16(rays.data() + base) : measure_group(rays, base, end);
#else
        const GroupMeasure g = measure_group(rays, base, end);
#endif
        if (!g.any) continue;
        const bool one_octant = g.neg_all == g.neg_any, near = within(g.lo, g.hi);
        ++groups;
        coherent += one_octant && near;
        together += near;
        octant += one_octant;
        end_together += g.ends_finite && within(g.elo, g.ehi);
    }
    BatchMeasures m;
    if (groups == 0) return m;
    const double g = double(groups);
    m.coherent = double(coherent) / g, m.together = double(together) / g, m.octant = double(octant) / g;
    m.end_together = double(end_together) / g;
    return m;
}

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
    const BatchMeasures m = measure_batch(rays, offer.packet_lanes, spread);
    c.why = PathChoice::Why::measured;
    c.group = offer.packet_lanes;
    c.coherent = m.coherent;
    c.one_octant = c.coherent >= packet_fraction;
    c.together = c.one_octant ? c.coherent : m.together;
    c.path = c.together >= packet_fraction ? TracePath::packet : TracePath::single;
    // Any-hit rays that share an octant wherever they start (shadow rays towards one light from a
    // view whose tile neighbours lie far apart on the model): the packet path, whose intervals
    // cull the nodes around the shared target. Chosen on the benchmark's shadow files (packet at or
    // above best on 8 of the 9 BVH cells of scripts/bench_vs_embree.sh's files), not on the
    // held-out set it is reported on. Any-hit rays that END together (shadow rays towards one
    // point light whose directions straddle an octant boundary: a light above a flat model or
    // inside a box) take packets too (tests/test_wide_paths.cpp).
    if (c.path == TracePath::single && q == Query::any) {
        c.octant_only = m.octant;
        if (c.octant_only >= packet_fraction) c.path = TracePath::packet;
        else if ((c.end_together = m.end_together) >= packet_fraction) c.path = TracePath::packet;
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
        } else if (c.end_together >= packet_fraction) {
            std::snprintf(buf, sizeof buf, "; any-hit rays, %.0f%% of the groups end within 5%% of the scene (one light): packets",
                          100.0 * c.end_together);
            why += buf;
        }
        break;
    }
    }
    if (c.not_offered != TracePath::best)
        return "no " + std::string(to_string(c.not_offered)) + " path here, took best: " + why;
    return why;
}

Layouts layouts_for(TracePath path) { return path == TracePath::scalar ? Layouts::scalar : Layouts::simd; }


}  // namespace arbor::accel
