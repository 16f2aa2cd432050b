#include "engine/render_settings.h"

#include <cstdio>

namespace arbor::engine {

namespace {
constexpr std::array<std::string_view, 5> integrator_name{"primary", "ao", "direct", "path", "cost"};
constexpr std::array<std::string_view, render_ray_kind_count> ray_kind_name{"primary", "shadow", "mirror", "diffuse", "ao"};
}  // namespace

std::string_view to_string(IntegratorKind k) { return integrator_name[std::size_t(k)]; }

std::optional<IntegratorKind> parse_integrator(std::string_view s) {
    for (std::size_t i = 0; i < integrator_name.size(); ++i)
        if (integrator_name[i] == s) return IntegratorKind(i);
    return std::nullopt;
}

std::string integrator_names() {
    std::string out;
    for (auto n : integrator_name) out += (out.empty() ? "" : ", ") + std::string(n);
    return out;
}

std::string_view to_string(RenderRayKind k) { return ray_kind_name[std::size_t(k)]; }

std::uint64_t RenderStats::total() const {
    std::uint64_t n = 0;
    for (auto r : rays) n += r;
    return n;
}

std::string RenderStats::summary() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.3g Mrays/s overall (%.3g rays in %.3f s)",
                  seconds > 0 ? double(total()) / seconds * 1e-6 : 0.0, double(total()), seconds);
    std::string out = buf;
    for (std::size_t k = 0; k < render_ray_kind_count; ++k) {
        if (rays[k] == 0) continue;
        const double per_thread = trace_seconds[k] / double(threads > 0 ? threads : 1);
        std::snprintf(buf, sizeof buf, "; %s %.3g at %.3g Mrays/s", ray_kind_name[k].data(), double(rays[k]),
                      per_thread > 0 ? double(rays[k]) / per_thread * 1e-6 : 0.0);
        out += buf;
    }
    return out;
}

}  // namespace arbor::engine
