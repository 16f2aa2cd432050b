#pragma once
/// A progress bar with the time left, drawn on stderr only when stderr is a terminal. Safe to
/// tick from many threads: one thread draws at a time, at most every 0.1 s; the others only count.
#include "accel/util/timer.h"

#include <atomic>
#include <mutex>
#include <string>

namespace arbor::engine {

class Progress {
public:
    /// `total` units of work; `enabled` false (or stderr not a terminal) draws nothing.
    /// `terminal`: stderr leads to a terminal although it is not one itself (rank 0 under mpirun
    /// writes into a pipe that mpirun copies to its terminal).
    Progress(std::string label, long total, bool enabled, bool terminal = false);
    ~Progress();  ///< erases the bar
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void tick(long units = 1);
    /// The text of the bar for `done` of `total` after `elapsed` seconds (for tests).
    static std::string bar(const std::string& label, long done, long total, double elapsed, int width = 30);

private:
    std::string label_;
    long total_;
    bool enabled_;
    std::atomic<long> done_{0};
    std::mutex draw_;
    double last_draw_ = -1.0;
    accel::Timer timer_;
};

}  // namespace arbor::engine
