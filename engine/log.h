#pragma once
/// One-line diagnostics on stderr. Warnings with the same text are printed once and counted.
#include <string>
#include <vector>

#include "engine/one_line.h"

namespace arbor::engine {

/// Collects warnings (e.g. from the loader) so that callers decide where they go.
struct Warnings {
    std::vector<std::string> lines;
    void add(const std::string& w) { lines.push_back(one_line(w)); }  ///< escaped to one line
    bool empty() const { return lines.empty(); }
};

void print_warnings(const Warnings& w);

}  // namespace arbor::engine
