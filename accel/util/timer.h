#pragma once
#include <chrono>

namespace arbor::accel {

/// Wall-clock stopwatch started at construction.
class Timer {
public:
    double ms() const { return std::chrono::duration<double, std::milli>(clock::now() - start_).count(); }
    double seconds() const { return ms() * 1e-3; }

private:
    using clock = std::chrono::steady_clock;
    clock::time_point start_ = clock::now();
};

}  // namespace arbor::accel
