#include "engine/log.h"

#include <cstdio>
#include <map>

namespace arbor::engine {

void print_warnings(const Warnings& w) {
    std::map<std::string, int> seen;
    std::vector<const std::string*> order;
    for (const auto& line : w.lines)
        if (seen[line]++ == 0) order.push_back(&line);
    for (const auto* line : order) {
        const int n = seen[*line];
        if (n > 1) std::fprintf(stderr, "warning: %s (%d times)\n", line->c_str(), n);
        else std::fprintf(stderr, "warning: %s\n", line->c_str());
    }
}

}  // namespace arbor::engine
