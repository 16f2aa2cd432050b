#include "accel/accel.h"

#include "accel/brute/brute_accel.h"
#include "accel/bvh/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/core/memory_estimate.h"
#include "accel/kdtree/kdtree_accel.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace arbor::accel {

namespace {
constexpr std::array<std::pair<AccelKind, std::string_view>, 6> kind_names{{
    {AccelKind::brute, "brute"},
    {AccelKind::bvh_median, "bvh-median"},
    {AccelKind::bvh_sah, "bvh-sah"},
    {AccelKind::lbvh, "lbvh"},
    {AccelKind::kdtree, "kdtree"},
    {AccelKind::automatic, "auto"},
}};
constexpr std::array<std::pair<TracePath, std::string_view>, 4> path_names{{
    {TracePath::best, "best"},
    {TracePath::scalar, "scalar"},
    {TracePath::packet, "packet"},
    {TracePath::single, "single"},
}};
}  // namespace

std::string_view to_string(AccelKind k) {
    for (const auto& [kind, name] : kind_names)
        if (kind == k) return name;
    return "?";
}

std::string_view to_string(TracePath p) {
    for (const auto& [path, name] : path_names)
        if (path == p) return name;
    return "?";
}

std::string_view to_string(Query q) { return q == Query::any ? "any" : "closest"; }

void Accel::check_counts() const {
    if (!offer_.counts)
        throw std::logic_error(std::string(to_string(kind_)) + ": the counted mode needs the scalar layout (built without it)");
}

std::optional<AccelKind> parse_accel_kind(std::string_view s) {
    for (const auto& [kind, name] : kind_names)
        if (name == s) return kind;
    return std::nullopt;
}

std::optional<TracePath> parse_trace_path(std::string_view s) {
    for (const auto& [path, name] : path_names)
        if (name == s) return path;
    return std::nullopt;
}

std::string accel_kind_names() {
    std::string out;
    for (const auto& [kind, name] : kind_names) {
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out;
}

namespace {
std::unique_ptr<Accel> build(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg) {
    switch (kind) {
    case AccelKind::brute: return std::make_unique<BruteAccel>(tris);
    case AccelKind::bvh_median: return build_bvh_accel(kind, tris, cfg, build_bvh_median);
    case AccelKind::bvh_sah: return build_bvh_accel(kind, tris, cfg, build_bvh_sah);
    case AccelKind::lbvh: return build_bvh_accel(kind, tris, cfg, build_lbvh);
    case AccelKind::kdtree: return make_kdtree_accel(tris, cfg);
    case AccelKind::automatic: throw std::invalid_argument("make_accel: resolve 'auto' before building");
    default: break;
    }
    throw std::invalid_argument("structure '" + std::string(to_string(kind)) + "' is not available in this build yet");
}
}  // namespace

std::unique_ptr<Accel> make_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg) {
    if (kind != AccelKind::automatic) check_build_memory(kind, tris.triangle_count(), cfg);
    std::unique_ptr<Accel> a = build(kind, tris, cfg);
    // A safety net behind the estimate (which bounds the BVHs and brute from above; the kd-tree
    // builder checks as it grows): a measured peak over the limit is refused too.
    if (cfg.max_memory != 0 && a->stats().build_peak_bytes > cfg.max_memory)
        throw MemoryLimitError(std::string(to_string(kind)) + ": the build reached " + std::to_string(a->stats().build_peak_bytes) +
                               " bytes, more than max_memory = " + std::to_string(cfg.max_memory) + " bytes");
    return a;
}

}  // namespace arbor::accel
