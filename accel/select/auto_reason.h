#pragma once
/// pick_accel's one-line reason, from the decision's data (auto_decision.h): which step decided,
/// with the prediction and margin or the probe's figures.
#include "accel/select/auto_decision.h"

#include <string>

namespace arbor::accel {

/// "lbvh/single 2.05 s (build 8.0 ms + 170 ns/ray)": a candidate's total and its parts; ns/ray is
/// the trace time over all the job's rays.
std::string describe(const AutoCandidate& c, double rays);

/// " (outside the model's 25% margin)": one contender.
std::string outside_margin_words(const ModelDecision& d);
/// " (within the model's 25% margin)".
std::string within_margin_words(const ModelDecision& d);
/// Why a planned probe does not run (no rays to time, or over which cap), for a plan that does not run.
std::string no_probe_words(const ProbePlan& plan, const AutoJob& job);

/// The reason when the model decided: its pick and prediction, what came next, `why`, auto's time.
std::string model_reason(const ModelDecision& d, const std::string& why, double auto_ms);

/// The reason when a probe decided: the measured candidates (smallest total first), the sample,
/// what the model had, auto's own time and, when `handed`, the pick's build handed over (handed_ms).
std::string probe_reason(const ModelDecision& d, const std::vector<AutoCandidate>& measured, std::size_t sample_rays,
                         double own_ms, bool handed, double handed_ms);

}  // namespace arbor::accel
