#include "accel/select/refit_select.h"

#include <cmath>
#include <cstdio>

#include "accel/select/reason_words.h"

namespace arbor::accel {

namespace {
/// Two decimals below 10 ms, down to zero (as these lines were first written).
constexpr MsWords refit_ms{true, false};
}  // namespace

std::optional<UpdateMode> parse_update_mode(std::string_view s) {
    if (s == "auto") return UpdateMode::automatic;
    if (s == "refit") return UpdateMode::refit;
    if (s == "rebuild") return UpdateMode::rebuild;
    return std::nullopt;
}

std::string ratio_words(double ratio) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3gx", ratio);
    return buf;
}

RefitChoice choose_refit(const RefitJob& job) {
    RefitChoice c;
    const double ratio = job.refit.ratio();
    c.extra_trace_ms = job.rays * job.ns_per_ray * (ratio - 1.0) * 1e-6;
    c.rebuild = c.extra_trace_ms > job.rebuild_ms;
    std::string sah = "SAH " + ratio_words(ratio) + " the last build's";
    if (job.rays <= 0.0) {
        c.reason = "refit: " + sah + "; no rays expected (" + job.rays_source + "), so nothing to win by a rebuild (" +
                   ms_words(job.rebuild_ms, refit_ms) + ")";
        return c;
    }
    const std::string rays = count_words(job.rays, false) + " rays (" + job.rays_source + ") at " +
                             std::to_string(std::llround(job.ns_per_ray)) + " ns each (" + job.ns_source + ")";
    c.reason = std::string(c.rebuild ? "rebuild: " : "refit: ") + sah + "; " + rays + " would take " +
               ms_words(c.extra_trace_ms, refit_ms) + " longer on the refitted tree, " + (c.rebuild ? "more" : "less") +
               " than a rebuild (" + ms_words(job.rebuild_ms, refit_ms) + ", the last build's time)";
    return c;
}

std::string forced_reason(UpdateMode mode, const RefitResult* refit) {
    const std::string what = mode == UpdateMode::rebuild ? "rebuild" : "refit";
    std::string s = what + ": asked for (mode " + what + ")";
    if (refit) s += "; SAH " + ratio_words(refit->ratio()) + " the last build's";
    return s;
}

std::string unsupported_reason(std::string_view why) { return "rebuild: " + std::string(why); }

}  // namespace arbor::accel
