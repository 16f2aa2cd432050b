#include "accel/select/auto_reason.h"

#include <cmath>
#include <cstdio>

#include "accel/select/reason_words.h"

namespace arbor::accel {

namespace {

std::string percent(double f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f%%", 100.0 * f);
    return buf;
}

std::string config_name(const AutoCandidate& c) {
    std::string s(to_string(c.kind));
    if (c.path != TracePath::best) s.append("/").append(to_string(c.path));
    return s;
}

/// The reason's start: "bvh-sah: packet path," (the path left out when the groups' paths are fixed).
std::string pick_words(const AutoCandidate& c) {
    std::string s(to_string(c.kind));
    s += ":";
    if (c.path != TracePath::best) s.append(" ").append(to_string(c.path)).append(" path,");
    return s;
}

/// "; next CONFIG, +X%": the best configuration other than all[ref], against it.
std::string next_after(const ModelDecision& d, std::size_t ref) {
    for (std::size_t i = 0; i < d.all.size(); ++i)
        if (i != ref) {
            const double x = d.all[i].c.total_ms / d.all[ref].c.total_ms - 1.0;
            return "; next " + describe(d.all[i].c, d.rays) + ", " + (x >= 0.0 ? "+" : "-") + percent(std::abs(x));
        }
    return std::string();
}

std::string job_words(const ModelDecision& d) { return " for " + count_words(d.rays) + " rays"; }

}  // namespace

std::string describe(const AutoCandidate& c, double rays) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.0f ns/ray", rays > 0 ? c.trace_ms * 1e6 / rays : 0.0);
    return config_name(c) + " " + ms_words(c.total_ms) + " (build " + ms_words(c.build_ms) + " + " + buf + ")";
}

std::string outside_margin_words(const ModelDecision& d) {
    return " (outside the model's " + percent(d.margin) + " margin)";
}

std::string within_margin_words(const ModelDecision& d) {
    return " (within the model's " + percent(d.margin) + " margin)";
}

std::string no_probe_words(const ProbePlan& plan, const AutoJob& job) {
    if (!plan.sampled) return "no rays to time";
    const double stake_cap = job.stake_share * plan.stake;
    if (plan.job_cap <= stake_cap)
        return "it would cost " + ms_words(plan.cost) + ", more than " + percent(job.probe_share) + " of the job (" +
               ms_words(plan.cap) + ")";
    return "it would cost " + ms_words(plan.cost) + ", more than " + percent(job.stake_share) +
           " of what it can win (" + ms_words(plan.cap) + " of " + ms_words(plan.stake) + ": the margin x " +
           (plan.structures.size() == 1 ? "the trace" : "the job") + ")";
}

namespace {
/// "; left out under max_memory, ...: lbvh 496.0 MiB", or nothing.
std::string left_out_words(const ModelDecision& d) {
    if (d.left_out.empty()) return {};
    std::string r = "; left out under max_memory, needing more before their build starts: ";
    for (std::size_t i = 0; i < d.left_out.size(); ++i) r += (i ? ", " : "") + d.left_out[i];
    return r;
}
}  // namespace

std::string model_reason(const ModelDecision& d, const std::string& why, double auto_ms) {
    const AutoCandidate& lead = d.all[d.lead].c;
    const std::string preferred =
        d.lead != 0 ? ", preferred within " + percent(d.prefer) + " of the best prediction" : std::string();
    return pick_words(lead) + " model: predicted " + describe(lead, d.rays) + job_words(d) + preferred +
           next_after(d, d.lead) + why + left_out_words(d) + "; auto " + ms_words(auto_ms);
}

std::string probe_reason(const ModelDecision& d, const std::vector<AutoCandidate>& measured, std::size_t sample_rays,
                         double own_ms, bool handed, double handed_ms) {
    const AutoCandidate& pick = measured.front();
    std::string r = pick_words(pick) + " probe: " + describe(pick, d.rays);
    for (std::size_t i = 1; i < measured.size(); ++i) r += (i == 1 ? "; next " : ", ") + describe(measured[i], d.rays);
    r += " (" + std::to_string(sample_rays) + " rays timed" + job_words(d) + "); the model had " +
         describe(d.all[0].c, d.rays) + next_after(d, 0) + within_margin_words(d) + "; auto " + ms_words(own_ms) +
         " (" + percent(own_ms / (pick.total_ms + own_ms)) + " of the job)" +
         (handed ? " + the pick's build " + ms_words(handed_ms) + ", handed over" : "");
    return r;
}

}  // namespace arbor::accel
