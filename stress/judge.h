#pragma once
/// Judging a structure's answers on a stress case against the double-precision oracle.
///
/// Each ray is traced twice, closest hit and any hit, and each answer gets one verdict:
/// - false miss: a miss where the oracle certainly hits (or where the ray promises a hit: from
///   inside a closed surface, or through the inside of a shared edge), or a closest hit behind a
///   surface the ray certainly crosses first (it leaked through it);
/// - false hit: a hit on a triangle the oracle rules out, or at a t farther from that triangle's
///   exact t than its error bound plus 1e-4 relative;
/// - double hit: a false hit of one particular kind, the same surface hit twice: a secondary ray
///   hitting the triangle it leaves, or a continuation ray (tnear just past a crossing) hitting
///   where the oracle sees nothing; and, in all-hits lists (judge_crossings), a ray whose
///   crossings of closed surfaces have the wrong parity with two crossings at one t (an edge or a
///   vertex counted by two triangles; the wrong parity without one is a false miss);
/// - accepted, otherwise. Rays in the oracle's band are counted apart; any answer a correct float
///   implementation could give is accepted there, nothing else.
#include "stress/oracle.h"
#include "stress/stress_case.h"

#include <span>
#include <string>
#include <vector>

namespace arbor::stress {

struct Tally {
    std::size_t rays = 0;        ///< rays of the case (each traced closest and any hit)
    std::size_t hits = 0;        ///< closest-hit answers that hit
    std::size_t band = 0;        ///< rays in the oracle's band
    std::size_t false_miss = 0;  ///< answers (closest or any), see above
    std::size_t false_hit = 0;
    std::size_t double_hit = 0;
    /// Largest |t - t_exact| / |t_exact| of an accepted hit of a ray outside the band (absolute
    /// when t_exact = 0); band rays may legitimately carry the large t error of a triangle seen
    /// nearly edge-on, so they are not mixed in.
    double max_dt = 0.0;
    std::vector<std::string> examples;  ///< the first failures, one line each

    std::size_t failures() const { return false_miss + false_hit + double_hit; }
};

/// Judges `closest` (intersect) and `any` (occluded) answers for the rays of `c`; `answers` are
/// oracle.answers(c.rays). `any` may be empty (closest only).
Tally judge(const StressCase& c, const Oracle& oracle, std::span<const OracleAnswer> answers,
            std::span<const Hit> closest, std::span<const Hit> any);

/// True when some ray of `c` promises a crossing parity (RayTag::parity).
bool has_parity(const StressCase& c);

/// Judges the all-hits lists of the rays of `c` (Accel::trace_all, one list per ray; hits on
/// triangles from c.parity_prims on are not counted) against their parity promises
/// (RayTag::parity) and adds the failures to `out`; the band does not apply: the
/// triangle test's tie rule makes a closed surface's crossings exact at edges and vertices too.
/// The rays' other answers are judged by judge(); `out.rays` is not changed.
void judge_crossings(const StressCase& c, std::span<const std::vector<Hit>> lists, Tally& out);

}  // namespace arbor::stress
