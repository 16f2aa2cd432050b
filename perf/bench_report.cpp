#include "perf/bench_report.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace arbor::perf {

namespace {

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
nlohmann::json stat(const Stat3& s) { return {{"median", num(s.median)}, {"min", num(s.min)}, {"max", num(s.max)}}; }

std::string fmt(double v, int prec = 2) {
    if (!std::isfinite(v)) return "–";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", prec, v);
    return buf;
}
std::string csv_num(double v) { return std::isfinite(v) ? fmt(v, 6) : ""; }
std::string err(long long v) { return v < 0 ? "–" : std::to_string(v); }
std::string budget_name(double b) {
    if (b >= 1e9) return fmt(b / 1e9, 0) + "G";
    if (b >= 1e6) return fmt(b / 1e6, 0) + "M";
    if (b >= 1e3) return fmt(b / 1e3, 0) + "k";
    return fmt(b, 0);
}

int max_threads(const BenchResult& r) {
    int t = 0;
    for (const auto& row : r.rows) t = std::max(t, row.threads);
    return t;
}

/// Scenes and kinds in the order they first appear.
std::vector<std::string> in_order(const BenchResult& r, std::string BenchRow::*field) {
    std::vector<std::string> out;
    for (const auto& row : r.rows)
        if (std::find(out.begin(), out.end(), row.*field) == out.end()) out.push_back(row.*field);
    return out;
}

const BenchRow* best_row(const BenchResult& r, const std::string& scene, const std::string& kind, int threads,
                         bool embree, bool default_embree_only = true) {
    const BenchRow* best = nullptr;
    for (const auto& row : r.rows) {
        if (row.scene != scene || row.kind != kind || row.threads != threads || row.embree != embree) continue;
        if (embree && default_embree_only && row.structure != "embree") continue;
        if (!best || row.mrays.median > best->mrays.median) best = &row;
    }
    return best;
}

void headline(std::ostringstream& md, const BenchResult& r) {
    const int t = max_threads(r);
    const auto kinds = in_order(r, &BenchRow::kind);
    md << "## Headline: best arbor structure per scene and ray kind (" << t << " threads)\n\n"
       << "Cell: structure/path, median Mrays/s, and its ratio to Embree's best mode and call in this run (named; "
          "the ratio to the default mode's best call follows when that is another one).\n\n| scene | tris |";
    for (const auto& k : kinds) md << ' ' << k << " |";
    md << "\n|---|---:|";
    for (std::size_t i = 0; i < kinds.size(); ++i) md << "---|";
    md << '\n';
    for (const auto& scene : in_order(r, &BenchRow::scene)) {
        std::size_t tris = 0;
        for (const auto& row : r.rows)
            if (row.scene == scene) tris = row.triangles;
        md << "| " << scene << " | " << tris << " |";
        for (const auto& k : kinds) {
            const BenchRow* a = best_row(r, scene, k, t, false);
            const BenchRow* e = best_row(r, scene, k, t, true);
            const BenchRow* eb = best_row(r, scene, k, t, true, false);
            if (!a && !e) {
                md << " |";
                continue;
            }
            md << ' ';
            if (a) md << a->structure << '/' << a->path << ' ' << fmt(a->mrays.median);
            if (a && eb && eb->mrays.median > 0) {
                md << " (" << fmt(a->mrays.median / eb->mrays.median) << "× " << eb->structure << '/' << eb->path;
                if (e && e != eb) md << "; " << fmt(a->ratio_embree) << "× default";
                md << ')';
            }
            if (!a && e) md << "embree/" << e->path << ' ' << fmt(e->mrays.median);
            md << " |";
        }
        md << '\n';
    }
    md << '\n';
}

void builds(std::ostringstream& md, const BenchResult& r) {
    md << "## Builds\n\nBuild wall time in ms (median, [min–max]) per thread count; structure statistics.\n\n"
       << "| scene | tris | structure | threads | build ms | bytes/tri | nodes | depth | SAH cost |\n"
       << "|---|---:|---|---:|---:|---:|---:|---:|---:|\n";
    std::set<std::tuple<std::string, std::string, int>> seen;
    for (const auto& row : r.rows) {
        if (!seen.insert({row.scene, row.structure, row.threads}).second) continue;
        md << "| " << row.scene << " | " << row.triangles << " | " << row.structure << " | " << row.threads << " | "
           << fmt(row.build_ms.median, 1) << " [" << fmt(row.build_ms.min, 1) << "–" << fmt(row.build_ms.max, 1)
           << "] | " << fmt(row.bytes_per_triangle, 1) << " | " << fmt(row.nodes, 0) << " | " << fmt(row.max_depth, 0)
           << " | " << fmt(row.sah_cost, 1) << " |\n";
    }
    md << '\n';
}

void matrix(std::ostringstream& md, const BenchResult& r) {
    md << "## Trace matrix\n\nMrays/s median [min–max] of the repeats; nodes and triangles per ray from the "
          "statistics mode; errors: against brute on a sample (bad/sample), against the structure's scalar path "
          "and against Embree's default (rtcIntersect1) on all rays.\n\n"
       << "| scene | kind | thr | structure | path | Mrays/s | nodes/ray | tris/ray | err brute | err scalar | "
          "err embree | × embree |\n|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& row : r.rows)
        md << "| " << row.scene << " | " << row.kind << " | " << row.threads << " | " << row.structure << " | "
           << row.path << " | " << fmt(row.mrays.median) << " [" << fmt(row.mrays.min) << "–" << fmt(row.mrays.max)
           << "] | " << fmt(row.nodes_per_ray, 1) << " | " << fmt(row.tris_per_ray, 1) << " | " << row.err_brute << "/"
           << row.brute_sample << " | " << err(row.err_scalar) << " | " << err(row.err_embree) << " | "
           << fmt(row.ratio_embree) << " |\n";
    md << '\n';
}

void totals(std::ostringstream& md, const BenchResult& r) {
    const int t = max_threads(r);
    md << "## Build + trace for a ray budget (" << t << " threads)\n\n"
       << "Per budget: the arbor structure (best path) with the smallest build + budget/throughput, its total in "
          "seconds, and the runner-up; Embree default for comparison.\n\n| scene | kind |";
    for (double b : r.budgets) md << ' ' << budget_name(b) << " rays |";
    md << "\n|---|---|";
    for (std::size_t i = 0; i < r.budgets.size(); ++i) md << "---|";
    md << '\n';
    for (const auto& scene : in_order(r, &BenchRow::scene))
        for (const auto& kind : in_order(r, &BenchRow::kind)) {
            bool any = false;
            std::string line = "| " + scene + " | " + kind + " |";
            for (std::size_t bi = 0; bi < r.budgets.size(); ++bi) {
                std::map<std::string, double> by_structure;  // best path per structure
                double embree = nan_value;
                for (const auto& row : r.rows) {
                    if (row.scene != scene || row.kind != kind || row.threads != t || bi >= row.total_ms.size()) continue;
                    if (row.embree) {
                        if (row.structure == "embree" && !(row.total_ms[bi] >= embree)) embree = row.total_ms[bi];
                        continue;
                    }
                    auto [it, fresh] = by_structure.emplace(row.structure, row.total_ms[bi]);
                    if (!fresh) it->second = std::min(it->second, row.total_ms[bi]);
                }
                std::vector<std::pair<double, std::string>> ranked;
                for (const auto& [s, ms] : by_structure) ranked.push_back({ms, s});
                std::sort(ranked.begin(), ranked.end());
                line += ' ';
                if (!ranked.empty()) {
                    any = true;
                    line += ranked[0].second + " " + fmt(ranked[0].first * 1e-3, 2) + " s";
                    if (ranked.size() > 1) line += " (" + ranked[1].second + " " + fmt(ranked[1].first * 1e-3, 2) + ")";
                }
                if (std::isfinite(embree)) line += "; embree " + fmt(embree * 1e-3, 2);
                line += " |";
            }
            if (any) md << line << '\n';
        }
    md << '\n';
}

/// The figures of the auto section (also printed by scripts/bench_summary.py from the JSON).
struct AutoSummary {
    std::size_t n = 0, within = 0, within_cpu = 0, within_pick = 0, floor_split = 0, floor_twice = 0;
    std::size_t floor_split_cpu = 0, floor_twice_cpu = 0, exact = 0, probed = 0;
    double worst = 0.0, worst_cpu = 0.0, sum_auto = 0.0, sum_best = 0.0, sum_default = 0.0;
};

AutoSummary summarize_autos(const std::vector<AutoRow>& autos) {
    AutoSummary s;
    for (const auto& a : autos) {
        const double regret = std::isfinite(a.regret) ? a.regret : 1e9;  // picked something untimed: a miss
        ++s.n;
        s.within += regret <= 0.10;
        s.within_cpu += std::isfinite(a.regret_cpu) && a.regret_cpu <= 0.10;
        s.within_pick += std::isfinite(a.regret_without_auto) && a.regret_without_auto <= 0.10;
        s.floor_split += std::isfinite(a.oracle_split_regret) && a.oracle_split_regret <= 0.10;
        s.floor_split_cpu += std::isfinite(a.oracle_split_regret_cpu) && a.oracle_split_regret_cpu <= 0.10;
        s.floor_twice += a.same_twice;
        s.floor_twice_cpu += a.same_twice_cpu;
        s.exact += a.picked == a.best && a.picked_path == a.best_path;
        s.probed += a.probed >= 0.5;
        s.worst = std::max(s.worst, regret);
        s.worst_cpu = std::max(s.worst_cpu, std::isfinite(a.regret_cpu) ? a.regret_cpu : 1e9);
        if (std::isfinite(a.auto_total_ms) && std::isfinite(a.default_ms)) {
            s.sum_auto += a.auto_total_ms, s.sum_best += a.best_ms, s.sum_default += a.default_ms;
        }
    }
    return s;
}

void autos(std::ostringstream& md, const BenchResult& r) {
    if (r.autos.empty()) return;
    const AutoSummary s = summarize_autos(r.autos);
    const double n = double(s.n);
    auto pct = [&](std::size_t k) { return fmt(100.0 * double(k) / n, 1) + "%"; };
    md << "## --accel auto\n\nThe whole job by the wall clock: auto's own time (shapes, model, probe) + the build of "
          "its pick (unless the probe built it) + budget x the pick's trace time per ray, against the best fixed "
          "(structure, path) choice's build + trace, all from the medians of interleaved repeats "
          "(perf/bench_auto.h).\n\n"
       << "On " << s.n << " (scene, kind, threads, budget) rows, **auto was within 10% of the best fixed choice on "
       << pct(s.within) << " of the rows by the wall clock, its own work counted** (target: 90%); worst "
       << fmt(1.0 + s.worst, 2) << "x (target: at most 1.5x); summed over the rows auto took "
       << fmt(s.sum_auto * 1e-3, 1) << " s, the best fixed choices " << fmt(s.sum_best * 1e-3, 1)
       << " s, always the default (bvh-sah, best path) " << fmt(s.sum_default * 1e-3, 1) << " s (auto / default "
       << fmt(s.sum_default > 0 ? s.sum_auto / s.sum_default : nan_value, 3) << "). A probe ran on "
       << pct(s.probed) << " of the rows; auto picked exactly the best (structure, path) on " << pct(s.exact)
       << ". Noise floor of the wall clock: the best fixed choice measured twice (even and odd repeats) is within 10% "
          "of itself on "
       << pct(s.floor_twice) << " of the rows; an oracle choosing on half of the repeats is within 10% on the other "
          "half on "
       << pct(s.floor_split) << ".\n\n"
       << "Other measures: without auto's own time (the pick alone) within 10% on " << pct(s.within_pick)
       << "; by CPU time (auto's CPU time / threads + the fastest build + the median trace CPU time / threads: an "
          "idle machine's totals) within 10% on "
       << pct(s.within_cpu) << ", worst " << fmt(1.0 + s.worst_cpu, 2) << "x (noise floors " << pct(s.floor_twice_cpu)
       << " measured twice, " << pct(s.floor_split_cpu) << " split oracle).\n\n"
       << "| scene | kind | thr | budget | auto picked | best fixed | auto ms | regret (wall, auto counted) | pick alone | CPU time | probe | reason |\n"
       << "|---|---|---:|---:|---|---|---:|---:|---:|---:|---:|---|\n";
    for (const auto& a : r.autos)
        md << "| " << a.scene << " | " << a.kind << " | " << a.threads << " | " << budget_name(a.budget) << " | "
           << a.picked << '/' << a.picked_path << " | " << a.best << '/' << a.best_path << " | " << fmt(a.auto_ms, 2)
           << " | " << fmt(100.0 * a.regret, 1) << "% | " << fmt(100.0 * a.regret_without_auto, 1) << "% | "
           << fmt(100.0 * a.regret_cpu, 1) << "% | " << fmt(100.0 * a.probed, 0) << "% | " << a.reason << " |\n";
    md << '\n';
}

}  // namespace

std::string to_json(const BenchResult& r) {
    nlohmann::json j;
    j["meta"] = {{"date", r.date},       {"command", r.command},     {"compiler", r.compiler},
                 {"libraries", r.libraries}, {"embree", r.embree},   {"hardware_threads", r.hardware_threads},
                 {"seconds", r.seconds}, {"budgets", r.budgets}, {"load_before", r.load_before},
                 {"load_after", r.load_after}};
    j["rows"] = nlohmann::json::array();
    for (const auto& row : r.rows) {
        nlohmann::json x;
        x["scene"] = row.scene, x["family"] = row.family, x["kind"] = row.kind, x["query"] = row.query;
        x["structure"] = row.structure, x["path"] = row.path, x["best_path"] = row.best_path, x["embree"] = row.embree, x["threads"] = row.threads;
        x["host"] = row.host;
        if (row.rank >= 0) x["rank"] = row.rank;
        x["triangles"] = row.triangles, x["rays"] = row.rays, x["validated_rays"] = row.validated_rays;
        x["build_ms"] = stat(row.build_ms), x["trace_ms"] = stat(row.trace_ms), x["mrays_per_s"] = stat(row.mrays);
        x["build_samples_ms"] = row.build_samples, x["trace_samples_ms"] = row.trace_samples;
        x["trace_cpu_ms"] = stat(row.trace_cpu_ms), x["trace_cpu_samples_ms"] = row.trace_cpu_samples;
        x["total_cpu_ms"] = nlohmann::json::array();
        for (double v : row.total_cpu_ms) x["total_cpu_ms"].push_back(num(v));
        x["nodes"] = num(row.nodes), x["leaves"] = num(row.leaves), x["max_depth"] = num(row.max_depth);
        x["sah_cost"] = num(row.sah_cost), x["bytes_per_triangle"] = num(row.bytes_per_triangle);
        x["nodes_per_ray"] = num(row.nodes_per_ray), x["tris_per_ray"] = num(row.tris_per_ray);
        x["brute_sample"] = row.brute_sample, x["err_brute"] = row.err_brute;
        x["err_scalar"] = row.err_scalar < 0 ? nlohmann::json(nullptr) : nlohmann::json(row.err_scalar);
        x["err_embree"] = row.err_embree < 0 ? nlohmann::json(nullptr) : nlohmann::json(row.err_embree);
        x["ratio_embree"] = num(row.ratio_embree);
        x["total_ms"] = nlohmann::json::array();
        for (double v : row.total_ms) x["total_ms"].push_back(num(v));
        x["shape"] = nlohmann::json::object();
        for (const auto& [k, v] : row.shape) x["shape"][k] = num(v);
        j["rows"].push_back(std::move(x));
    }
    j["auto"] = nlohmann::json::array();
    for (const auto& a : r.autos)
        j["auto"].push_back({{"scene", a.scene}, {"kind", a.kind}, {"threads", a.threads}, {"budget", a.budget},
                             {"picked", a.picked}, {"picked_path", a.picked_path}, {"best", a.best},
                             {"best_path", a.best_path}, {"auto_ms", num(a.auto_ms)},
                             {"auto_total_ms", num(a.auto_total_ms)}, {"best_ms", num(a.best_ms)},
                             {"default_ms", num(a.default_ms)}, {"regret", num(a.regret)},
                             {"regret_without_auto", num(a.regret_without_auto)}, {"regret_cpu", num(a.regret_cpu)},
                             {"probed", num(a.probed)}, {"oracle_split_regret", num(a.oracle_split_regret)},
                             {"oracle_split_regret_cpu", num(a.oracle_split_regret_cpu)},
                             {"same_twice", a.same_twice}, {"same_twice_cpu", a.same_twice_cpu},
                             {"reason", a.reason}});
    j["notes"] = r.notes;
    return j.dump() + "\n";
}

std::string to_csv(const BenchResult& r) {
    std::ostringstream out;
    out << "scene,family,kind,query,structure,path,best_path,embree,threads,triangles,rays,validated_rays,build_ms,build_ms_min,build_ms_max,"
           "trace_ms,trace_ms_min,trace_ms_max,mrays_per_s,mrays_per_s_min,mrays_per_s_max,nodes,leaves,max_depth,"
           "sah_cost,bytes_per_triangle,nodes_per_ray,tris_per_ray,brute_sample,err_brute,err_scalar,err_embree,"
           "ratio_embree";
    for (double b : r.budgets) out << ",total_ms_" << budget_name(b);
    out << '\n';
    for (const auto& row : r.rows) {
        out << row.scene << ',' << row.family << ',' << row.kind << ',' << row.query << ',' << row.structure << ','
            << row.path << ',' << (row.best_path ? 1 : 0) << ',' << (row.embree ? 1 : 0) << ',' << row.threads << ',' << row.triangles << ',' << row.rays << ',' << row.validated_rays;
        for (const Stat3* s : {&row.build_ms, &row.trace_ms, &row.mrays})
            out << ',' << csv_num(s->median) << ',' << csv_num(s->min) << ',' << csv_num(s->max);
        for (double v : {row.nodes, row.leaves, row.max_depth, row.sah_cost, row.bytes_per_triangle, row.nodes_per_ray,
                         row.tris_per_ray})
            out << ',' << csv_num(v);
        out << ',' << row.brute_sample << ',' << row.err_brute << ',' << (row.err_scalar < 0 ? "" : std::to_string(row.err_scalar))
            << ',' << (row.err_embree < 0 ? "" : std::to_string(row.err_embree)) << ',' << csv_num(row.ratio_embree);
        for (double v : row.total_ms) out << ',' << csv_num(v);
        out << '\n';
    }
    return out.str();
}

std::string to_markdown(const BenchResult& r) {
    std::ostringstream md;
    md << "# arbor benchmark " << r.date << "\n\n"
       << "- command: `" << r.command << "`\n- wall time: " << fmt(r.seconds, 1) << " s\n- hardware threads: "
       << r.hardware_threads << " (load average " << r.load_before << " at the start, " << r.load_after
       << " at the end)\n- compiler: " << r.compiler << "\n- libraries: " << r.libraries << "\n- peer: "
       << r.embree << "\n\n";
    headline(md, r);
    totals(md, r);
    autos(md, r);
    builds(md, r);
    matrix(md, r);
    if (!r.notes.empty()) {
        md << "## Notes\n\n";
        for (const auto& n : r.notes) md << "- " << n << '\n';
    }
    return md.str();
}

void write_reports(const BenchResult& r, const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw engine::InputError(dir + ": cannot create directory (" + ec.message() + ")");
    engine::write_file_atomic(dir + "/bench.json", to_json(r));
    engine::write_file_atomic(dir + "/bench.csv", to_csv(r));
    engine::write_file_atomic(dir + "/bench.md", to_markdown(r));
}

}  // namespace arbor::perf
