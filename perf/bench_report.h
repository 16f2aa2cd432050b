#pragma once
/// Writing benchmark results: JSON and CSV for machines, Markdown for people.
#include "perf/bench_result.h"

#include <string>

namespace arbor::perf {

/// The whole result as one JSON document: {"meta": {...}, "rows": [...], "auto": [...], "notes": [...]}.
/// NaN values become null.
std::string to_json(const BenchResult& r);
/// One line per row, header first; NaN values are empty fields.
std::string to_csv(const BenchResult& r);
/// Tables: headline (best arbor structure per scene and ray kind against Embree), builds, the
/// full trace matrix with its error columns, totals per ray budget, auto, notes.
std::string to_markdown(const BenchResult& r);

/// Writes bench.json, bench.csv and bench.md into `dir` (created if missing), atomically each.
/// Throws engine::InputError naming the path when it cannot.
void write_reports(const BenchResult& r, const std::string& dir);

}  // namespace arbor::perf
