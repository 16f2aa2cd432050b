#include "perf/paths_report.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

namespace arbor::perf {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, a, b, c);
    return buf;
}

using Cell = std::pair<std::string, std::string>;  // scene, kind

/// Embree's fastest call per cell: (Mrays/s, call).
std::map<Cell, std::pair<double, std::string>> embree_best(const std::vector<PathsRow>& rows) {
    std::map<Cell, std::pair<double, std::string>> best;
    for (const PathsRow& r : rows)
        if (r.embree) {
            auto& b = best[{r.scene, r.kind}];
            if (r.mrays > b.first) b = {r.mrays, r.path};
        }
    return best;
}

/// The Embree calls timed in `rows`, in order of appearance, joined by `sep` ("1, 8, 16, 1M" under
/// Embree 3; Embree 4 has no 1M): the reports name only the calls that ran.
std::string embree_calls_seen(const std::vector<PathsRow>& rows, const char* sep) {
    std::vector<std::string> calls;
    for (const PathsRow& r : rows)
        if (r.embree && std::find(calls.begin(), calls.end(), r.path) == calls.end()) calls.push_back(r.path);
    std::string s;
    for (const std::string& c : calls) s += (s.empty() ? "" : sep) + c;
    return s;
}

/// The q-quantile of sorted values, linearly interpolated.
double quantile(const std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    const double x = q * double(v.size() - 1);
    const std::size_t i = std::size_t(x);
    const double f = x - double(i);
    return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}

/// Ratios of one (kind, structure, measure) over the cells, with the errors of the rows behind them.
struct Series {
    std::vector<std::pair<double, std::string>> ratios;  // ratio, cell
    long long err = 0, err_brute = 0, err_embree = 0, brute_rays = 0, rays = 0, paths = 0;
};

}  // namespace

std::string paths_report(const std::vector<PathsRow>& rows, std::size_t brute_sample) {
    std::ostringstream s;
    const auto ebest = embree_best(rows);
    std::map<Cell, std::map<std::string, std::pair<double, std::string>>> arbor_best;  // per structure
    std::map<Cell, std::map<std::string, double>> auto_path;                          // TracePath::best
    std::vector<Cell> cells;
    std::vector<std::string> structures;
    for (const PathsRow& r : rows) {
        const Cell c{r.scene, r.kind};
        if (std::find(cells.begin(), cells.end(), c) == cells.end()) cells.push_back(c);
        if (r.embree) continue;
        if (std::find(structures.begin(), structures.end(), r.structure) == structures.end()) structures.push_back(r.structure);
        auto& b = arbor_best[c][r.structure];
        if (r.mrays > b.first) b = {r.mrays, r.path};
        if (r.path == "best") auto_path[c][r.structure] = r.mrays;
    }
    s << "## arbor's fastest path / Embree's fastest call\n\n";
    s << "Per structure: its fastest path's median Mrays/s over Embree's fastest call (of "
      << embree_calls_seen(rows, ", ")
      << ") on the same rays; "
         "in brackets the path, and `best` = the path TracePath::best picked by itself.\n\n";
    s << "| scene | kind | Embree best |";
    for (const auto& st : structures) s << " " << st << " |";
    s << "\n|---|---|---|";
    for (std::size_t i = 0; i < structures.size(); ++i) s << "---|";
    s << "\n";
    for (const Cell& c : cells) {
        const auto e = ebest.count(c) ? ebest.at(c) : std::pair<double, std::string>{0.0, "-"};
        s << "| " << c.first << " | " << c.second << " | " << e.second << ": " << fmt("%.2f", e.first) << " |";
        for (const auto& st : structures) {
            const auto it = arbor_best[c].find(st);
            if (it == arbor_best[c].end() || e.first <= 0) {
                s << " - |";
                continue;
            }
            s << " **" << fmt("%.2f", it->second.first / e.first) << "x** (" << it->second.second;
            const auto ap = auto_path[c].find(st);
            if (ap != auto_path[c].end() && it->second.second != "best") s << "; best " << fmt("%.2f", ap->second / e.first) << "x";
            s << ") |";
        }
        s << "\n";
    }
    s << "\n## Every configuration\n\n";
    s << "Mrays/s median [min-max] over the repeats; `x Embree` = over Embree's fastest call in the same cell; errors = "
         "answers disagreeing with the structure's scalar path on all rays (Embree: with the first structure's scalar path; "
         "rayfile.md rule, any hit: hit or miss); vs Embree = with Embree's rtcIntersect1 on all rays.\n\n";
    s << "| scene | kind | configuration | Mrays/s | x Embree | errors | errors vs brute (sample of " << brute_sample
      << ") | errors vs Embree |\n|---|---|---|---:|---:|---:|---:|---:|\n";
    for (const PathsRow& r : rows) {
        const auto it = ebest.find({r.scene, r.kind});
        const double b = it == ebest.end() ? 0.0 : it->second.first;
        s << "| " << r.scene << " | " << r.kind << " | " << r.structure << " " << r.path << " | "
          << fmt("%.2f [%.2f-%.2f]", r.mrays, r.lo, r.hi) << " | " << fmt("%.2f", b > 0 ? r.mrays / b : 0.0) << " | " << r.err
          << " | " << r.err_brute << " | " << (r.err_embree < 0 ? std::string("-") : std::to_string(r.err_embree)) << " |\n";
    }
    return s.str();
}

std::string paths_distribution(const std::vector<PathsRow>& rows, std::size_t brute_sample) {
    const auto ebest = embree_best(rows);
    std::vector<std::string> kinds, structures;
    // (kind, structure, measure) -> series; measure 0 = default path `best`, 1 = fastest path.
    std::map<std::tuple<std::string, std::string, int>, Series> series;
    std::map<Cell, std::vector<const PathsRow*>> by_cell;
    std::vector<Cell> cells;
    for (const PathsRow& r : rows) {
        const Cell c{r.scene, r.kind};
        if (!by_cell.count(c)) cells.push_back(c);
        by_cell[c].push_back(&r);
        if (std::find(kinds.begin(), kinds.end(), r.kind) == kinds.end()) kinds.push_back(r.kind);
        if (!r.embree && std::find(structures.begin(), structures.end(), r.structure) == structures.end())
            structures.push_back(r.structure);
    }
    auto add = [&](Series& se, const PathsRow& r, double e, const Cell& c) {
        se.ratios.push_back({r.mrays / e, c.first + " (" + r.structure + " " + r.path + ")"});
        se.err += std::max(r.err, 0LL);
        se.err_brute += std::max(r.err_brute, 0LL);
        se.err_embree += std::max(r.err_embree, 0LL);
        se.brute_rays += static_cast<long long>(brute_sample);
        se.rays += static_cast<long long>(r.rays);
        ++se.paths;
    };
    for (const Cell& c : cells) {
        const auto it = ebest.find(c);
        if (it == ebest.end() || it->second.first <= 0) continue;
        const double e = it->second.first;
        const PathsRow* overall = nullptr;
        for (const std::string& st : structures) {
            const PathsRow *dflt = nullptr, *fastest = nullptr;
            for (const PathsRow* r : by_cell[c]) {
                if (r->embree || r->structure != st) continue;
                if (r->path == "best") dflt = r;
                if (r->path != "scalar" && (!fastest || r->mrays > fastest->mrays)) fastest = r;
            }
            if (dflt) add(series[{c.second, st, 0}], *dflt, e, c);
            if (fastest) add(series[{c.second, st, 1}], *fastest, e, c);
            if (dflt && (!overall || dflt->mrays > overall->mrays)) overall = dflt;
        }
        if (overall) add(series[{c.second, "arbor", 0}], *overall, e, c);
    }
    std::ostringstream s;
    s << "## Distribution over the cells: arbor / Embree's fastest call\n\n"
         "Per ray kind and structure, over every cell (scene and view): the ratio of the structure's median "
         "Mrays/s on its default path (`best`, what `arbor trace` runs) — and on its fastest SIMD path — to the "
         "median of Embree's fastest call in the same cell (of rtcIntersect"
      << embree_calls_seen(rows, "/")
      << ", coherent flag on primary and shadow rays). `arbor` = the faster of the structures' default paths in "
         "each cell. Accuracy of the same configurations, summed over the cells: disagreements with the "
         "structure's scalar path (all rays), with brute (a sample of "
      << brute_sample
      << " rays per cell) and with Embree's rtcIntersect1 (all rays; any hit: hit or miss; closest hit: the rayfile.md "
         "rule, so a tie between two triangles at equal t is no disagreement).\n\n"
         "| kind | structure | path | cells | min | q1 | median | q3 | max | worst cell | errors vs scalar "
         "| vs brute | vs Embree |\n"
         "|---|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n";
    std::vector<std::string> order = structures;
    order.push_back("arbor");
    for (const std::string& k : kinds)
        for (const std::string& st : order)
            for (int m = 0; m < 2; ++m) {
                const auto it = series.find({k, st, m});
                if (it == series.end() || it->second.ratios.empty()) continue;
                Series se = it->second;
                std::sort(se.ratios.begin(), se.ratios.end());
                std::vector<double> v;
                for (const auto& p : se.ratios) v.push_back(p.first);
                s << "| " << k << " | " << (st == "arbor" ? "**arbor**" : st) << " | " << (m == 0 ? "default" : "fastest") << " | "
                  << v.size() << " | " << fmt("%.2f", v.front()) << " | " << fmt("%.2f", quantile(v, 0.25)) << " | **"
                  << fmt("%.2f", quantile(v, 0.5)) << "** | " << fmt("%.2f", quantile(v, 0.75)) << " | " << fmt("%.2f", v.back())
                  << " | " << se.ratios.front().second << " | " << se.err << " / " << se.rays << " | " << se.err_brute << " / "
                  << se.brute_rays << " | " << se.err_embree << " / " << se.rays << " |\n";
            }
    return s.str();
}

}  // namespace arbor::perf
