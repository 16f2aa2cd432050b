#pragma once
/// The steps of pick_accel's decision as data (auto_select.cpp makes them, auto_reason.cpp puts
/// them in words): what the model predicts, which configurations contend, and what a probe would
/// cost. Internal to select/.
#include "accel/select/auto_select.h"

#include <cstddef>
#include <string>
#include <vector>

namespace arbor::accel {

/// A configuration being weighed: the candidate plus the path and predicted ns of each group.
struct Weighed {
    AutoCandidate c;
    std::vector<TracePath> paths;  ///< per group
    std::vector<double> ns;        ///< per group, predicted
};

/// The cost model's decision over every configuration it can weigh.
struct ModelDecision {
    std::vector<Weighed> all;             ///< smallest predicted total first (never empty)
    std::size_t lead = 0;                 ///< the model's pick: all[0], or the preferred structure's best
    double margin = 0.0;                  ///< the model's margin
    double prefer = 0.0;                  ///< the share within which the preferred structure is taken
    std::vector<std::size_t> contenders;  ///< within the margin of all[0], then the other paths of their structures
    std::size_t within_margin = 0;        ///< how many of contenders are within the margin
    double rays = 0.0;                    ///< the job's rays, all groups
    /// Structures left out under BuildConfig::max_memory: what each would need before its build
    /// starts is more (factory/memory_estimate.h, build_start_bytes), in words ("lbvh 496.0 MiB").
    std::vector<std::string> left_out;
};

/// What a probe of the contenders would cost, against its two caps.
struct ProbePlan {
    std::vector<AccelKind> structures;  ///< the structures it builds, the best prediction's first
    double cost = 0.0;                  ///< predicted: the builds not handed over plus the sample timings
    double job_cap = 0.0;               ///< AutoJob::probe_share of the job
    double stake = 0.0;                 ///< what it can win: the margin times the contenders' unshared part
    double cap = 0.0;                   ///< min(job_cap, AutoJob::stake_share * stake)
    std::size_t probed_configs = 0;     ///< contenders whose structure it builds
    bool sampled = false;               ///< some group has rays to time
    bool runs() const { return cost <= cap && probed_configs >= 2 && sampled; }
};

}  // namespace arbor::accel
