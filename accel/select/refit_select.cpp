#include "accel/select/refit_select.h"

#include <cmath>
#include <cstdio>

namespace arbor::accel {

namespace {

std::string ms_words(double ms) {
    char buf[32];
    if (ms >= 1000.0) std::snprintf(buf, sizeof buf, "%.2f s", ms * 1e-3);
    else if (ms >= 10.0) std::snprintf(buf, sizeof buf, "%.0f ms", ms);
    else std::snprintf(buf, sizeof buf, "%.2f ms", ms);
    return buf;
}

std::string count_words(double n) {
    char buf[32];
    if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.3gM", n * 1e-6);
    else if (n >= 1e3) std::snprintf(buf, sizeof buf, "%.3gk", n * 1e-3);
    else std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}

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
                   ms_words(job.rebuild_ms) + ")";
        return c;
    }
    const std::string rays = count_words(job.rays) + " rays (" + job.rays_source + ") at " +
                             std::to_string(std::llround(job.ns_per_ray)) +
                             " ns each (" + job.ns_source + ")";
    c.reason = std::string(c.rebuild ? "rebuild: " : "refit: ") + sah + "; " + rays + " would take " +
               ms_words(c.extra_trace_ms) + " longer on the refitted tree, " + (c.rebuild ? "more" : "less") +
               " than a rebuild (" + ms_words(job.rebuild_ms) + ", the last build's time)";
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
