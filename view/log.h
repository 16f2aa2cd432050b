#pragma once
/// The viewer's log: one line on standard error per event, "arbor view: " first, flushed at once
/// (the tests read the log while the server runs).
#include <cstdio>
#include <string>

namespace arbor::view {

inline void log_line(const std::string& s) {
    std::fprintf(stderr, "arbor view: %s\n", s.c_str());
    std::fflush(stderr);
}

}  // namespace arbor::view
