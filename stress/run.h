#pragma once
/// Running the stiff cases over structures and traversal paths: one row per case x structure x
/// path, as `arbor stress` prints it and the doctest suite checks it.
#include "accel/interface/accel.h"
#include "stress/judge.h"

#include <functional>
#include <memory>
#include <vector>

namespace arbor::stress {

struct StressRow {
    std::string case_name;
    accel::AccelKind kind = accel::AccelKind::brute;
    accel::TracePath path = accel::TracePath::scalar;
    /// The kd-tree's SIMD walk of this row (accel::kd_walk_name); empty otherwise.
    std::string walk;
    Tally tally;
    double build_ms = 0.0;
    double ns_per_ray = 0.0;  ///< closest-hit queries on one thread (fastest of a few passes)
    /// From the counted mode (closest hit, scalar loop) when the structure offers it.
    bool counted = false;
    double nodes_per_ray = 0.0, triangles_per_ray = 0.0;
    std::int64_t dropped = 0;  ///< stats().dropped_nonfinite
    std::string problem;       ///< a failed check besides the answers (dropped count, slow NaN rays)

    bool failed() const { return tally.failures() != 0 || !problem.empty(); }
};

/// A case with the oracle's answers, computed once for all structures.
struct PreparedCase {
    const StressCase* c = nullptr;
    std::unique_ptr<Oracle> oracle;
    std::vector<OracleAnswer> answers;
};
PreparedCase prepare(const StressCase& c);

/// Every structure make_accel can build in this binary (`auto` excluded), in AccelKind order.
std::vector<accel::AccelKind> buildable_kinds();
/// `scalar`, then `single` and `packet` when `a` implements them (Accel::offer).
std::vector<accel::TracePath> paths_of(const accel::Accel& a);

/// Builds `kind` over the case's mesh and judges every path (closest and any hit); the kd-tree's
/// `single` and `packet` for each of its walks (KdBlockConfig::walk: cfg's, then a build for each
/// other). Also checks
/// the dropped-triangle count (when the case sets one) and, through the counted mode when the
/// structure implements it, that untraceable rays visit no node and no triangle.
std::vector<StressRow> run_case(const PreparedCase& p, accel::AccelKind kind, const accel::BuildConfig& cfg = {});

}  // namespace arbor::stress
