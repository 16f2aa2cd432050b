#pragma once
/// The Markdown report of `arbor-bench paths`: the ratio table (per scene and ray kind, each structure's
/// fastest path over Embree's fastest call), every configuration, and — for many cells, e.g. the
/// held-out views of scripts/bench_heldout.sh — the distribution of those ratios per ray kind and
/// structure with the accuracy of the same configurations beside it.
#include <string>
#include <vector>

namespace arbor::perf {

/// One timed configuration on one cell (scene or scene/view, ray kind).
struct PathsRow {
    std::string scene, kind, structure, path;
    double mrays, lo, hi;        ///< median, slowest and fastest repeat (Mrays/s)
    long long err, err_brute;    ///< disagreements with the scalar path (all rays), with brute (sample)
    long long err_embree = -1;   ///< disagreements with Embree's rtcIntersect1 (all rays; -1: not compared)
    std::size_t rays = 0;
    bool embree;
};

/// The ratio table and every configuration (brute_sample: rays per cell checked against brute).
std::string paths_report(const std::vector<PathsRow>& rows, std::size_t brute_sample);

/// Per ray kind and structure, over all cells: min, lower quartile, median, upper quartile and
/// max of (the structure's default path `best` / Embree's fastest call) and of (its fastest path /
/// Embree's fastest call), the worst cell, and the errors of those configurations summed over the
/// cells; "arbor" = the faster of the structures' default paths in each cell.
std::string paths_distribution(const std::vector<PathsRow>& rows, std::size_t brute_sample);

}  // namespace arbor::perf
