#pragma once
/// One-line diagnostics on stderr. Warnings with the same text are printed once and counted.
#include <string>
#include <vector>

namespace arbor::engine {

/// Collects warnings (e.g. from the loader) so that callers decide where they go.
struct Warnings {
    std::vector<std::string> lines;
    void add(std::string w) { lines.push_back(std::move(w)); }
    bool empty() const { return lines.empty(); }
};

void print_warnings(const Warnings& w);

}  // namespace arbor::engine
