#include "accel/interface/accel.h"

#include "accel/bvh/bvh2_winding.h"

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

RefitResult Accel::refit(const TriangleView&) {
    throw std::logic_error(std::string(to_string(kind_)) + ": cannot be refit (" + std::string(refit_unsupported()) + ")");
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

std::unique_ptr<WindingTree> Accel::make_winding_tree(const TriangleView& tris) const {
    return make_internal_winding(tris);
}

}  // namespace arbor::accel
