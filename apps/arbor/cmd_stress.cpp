/// `arbor stress [--accel NAME] [--json] [--model FILE]... [--small] [--case NAME]... [--threads N]`
/// (spec/cli.md): the stiff-case suite over every structure and traversal path (the kd-tree's
/// SIMD paths for each walk, "kdtree/tight-cells", "kdtree/cells", "kdtree/ropes"), as a table of
/// case x structure x path -> rays, hit rate, band, false misses, false hits, double hits,
/// max |dt| against the double-precision oracle, work and time per ray. Exits 1 when any false
/// miss, false hit or double hit (or a failed structural check) was found, 0 otherwise.
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "engine/error.h"
#include "engine/mesh_loader.h"
#include "stress/run.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace arbor::app {

namespace {

struct StressOptions {
    std::string accel;
    std::vector<std::string> models, only;
    accel::BuildConfig build;
    bool json = false, small = false;
    int threads = 0;
};

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

/// The structure of a row: its name, and the kd-tree's walk for its SIMD paths ("kdtree/cells").
std::string accel_name(const stress::StressRow& r) {
    return std::string(accel::to_string(r.kind)) + (r.walk.empty() ? "" : "/" + r.walk);
}

void print_header() {
    std::printf("%-20s %-18s %-6s %7s %6s %6s %6s %6s %6s %9s %9s %9s %8s\n", "case", "accel", "path", "rays", "hit%",
                "band", "f.miss", "f.hit", "double", "max|dt|", "nodes/ray", "tris/ray", "ns/ray");
}

void print_row(const stress::StressRow& r) {
    const auto& t = r.tally;
    std::printf("%-20s %-18s %-6s %7zu %6s %6zu %6zu %6zu %6zu %9s %9s %9s %8s%s\n", r.case_name.c_str(),
                accel_name(r).c_str(), std::string(accel::to_string(r.path)).c_str(), t.rays,
                fmt("%.1f", t.rays ? 100.0 * double(t.hits) / double(t.rays) : 0.0).c_str(), t.band, t.false_miss,
                t.false_hit, t.double_hit, fmt("%.1e", t.max_dt).c_str(),
                r.counted ? fmt("%.1f", r.nodes_per_ray).c_str() : "-", r.counted ? fmt("%.1f", r.triangles_per_ray).c_str() : "-",
                fmt("%.0f", r.ns_per_ray).c_str(), r.failed() ? "  FAIL" : "");
    std::fflush(stdout);
}

nlohmann::json row_json(const stress::StressRow& r) {
    const auto& t = r.tally;
    nlohmann::json j;
    j["case"] = r.case_name;
    j["accel"] = accel::to_string(r.kind);
    j["path"] = accel::to_string(r.path);
    if (!r.walk.empty()) j["kd_walk"] = r.walk;
    j["rays"] = t.rays;
    j["hits"] = t.hits;
    j["band"] = t.band;
    j["false_misses"] = t.false_miss;
    j["false_hits"] = t.false_hit;
    j["double_hits"] = t.double_hit;
    j["max_dt"] = t.max_dt;
    j["build_ms"] = r.build_ms;
    j["ns_per_ray"] = r.ns_per_ray;
    if (r.counted) j["nodes_per_ray"] = r.nodes_per_ray, j["triangles_per_ray"] = r.triangles_per_ray;
    j["dropped_nonfinite"] = r.dropped;
    j["problem"] = r.problem;
    j["examples"] = t.examples;
    j["ok"] = !r.failed();
    return j;
}

bool selected(const std::vector<std::string>& only, const std::string& name) {
    if (only.empty()) return true;
    for (const auto& o : only)
        if (name.find(o) != std::string::npos) return true;
    return false;
}

int run_stress(const StressOptions& o) {
    const auto limit = limit_threads(o.threads);
    const stress::Size size = o.small ? stress::Size::small : stress::Size::full;
    std::vector<accel::AccelKind> kinds = stress::buildable_kinds();
    if (!o.accel.empty()) {
        const auto k = accel::parse_accel_kind(o.accel);
        if (!k || *k == accel::AccelKind::automatic) throw OptionError("--accel: name a structure for stress (not '" + o.accel + "')");
        if (std::find(kinds.begin(), kinds.end(), *k) == kinds.end())
            throw OptionError("--accel: structure '" + o.accel + "' is not available in this build yet");
        kinds = {*k};
    }
    std::vector<stress::StressCase> cases;
    for (const std::string& path : o.models) {
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_mesh(path, w);
        try {
            cases.push_back(stress::make_closed_model_case(mesh, std::filesystem::path(path).stem().string(), size));
        } catch (const std::invalid_argument& e) {
            throw engine::InputError(path, 0, std::string("--model: ") + e.what());
        }
    }
    for (auto& c : stress::make_stress_cases(size)) cases.push_back(std::move(c));
    std::erase_if(cases, [&](const stress::StressCase& c) { return !selected(o.only, c.name); });
    if (cases.empty()) throw OptionError("--case: no case matches");

    if (!o.json) print_header();
    nlohmann::json rows = nlohmann::json::array();
    std::vector<std::string> failures;
    std::size_t fm = 0, fh = 0, dh = 0, band = 0, nrows = 0;
    for (const auto& c : cases) {
        const stress::PreparedCase p = stress::prepare(c);
        for (accel::AccelKind k : kinds)
            for (const auto& r : stress::run_case(p, k, o.build)) {
                ++nrows;
                fm += r.tally.false_miss, fh += r.tally.false_hit, dh += r.tally.double_hit, band += r.tally.band;
                if (o.json) rows.push_back(row_json(r));
                else print_row(r);
                if (r.failed()) {
                    const std::string where = r.case_name + " / " + accel_name(r) + " / " +
                                              std::string(accel::to_string(r.path)) + ": ";
                    if (!r.problem.empty()) failures.push_back(where + r.problem);
                    for (const auto& e : r.tally.examples) failures.push_back(where + e);
                }
            }
    }
    const bool ok = failures.empty();
    if (o.json) {
        nlohmann::json j;
        j["rows"] = rows;
        j["cases"] = cases.size();
        j["false_misses"] = fm, j["false_hits"] = fh, j["double_hits"] = dh;
        j["ok"] = ok;
        j["threads"] = active_threads();
        std::cout << j.dump() << '\n';
    } else {
        std::printf("%zu cases, %zu rows: %zu false misses, %zu false hits, %zu double hits (%zu band rays accepted): %s\n",
                    cases.size(), nrows, fm, fh, dh, band, ok ? "PASS" : "FAIL");
        for (const auto& f : failures) std::printf("  %s\n", f.c_str());
    }
    return ok ? 0 : 1;
}

}  // namespace

Run add_stress(CLI::App& cmd) {
    auto o = std::make_shared<StressOptions>();
    add_accel_option(cmd, o->accel);
    add_build_options(cmd, o->build);
    cmd.add_option("--model", o->models, "also a watertightness case on this closed OBJ model (repeatable)")
        ->check(CLI::ExistingFile);
    cmd.add_option("--case", o->only, "run only the cases whose name contains this (repeatable)");
    cmd.add_flag("--small", o->small, "the doctest sizes (seconds instead of a minute)");
    add_threads_option(cmd, o->threads);
    cmd.add_flag("--json", o->json, "one JSON object on standard output");
    return [o] { return run_stress(*o); };
}

}  // namespace arbor::app
