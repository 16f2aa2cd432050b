#include "engine/progress.h"

#include <cstdio>
#include <unistd.h>

namespace arbor::engine {

Progress::Progress(std::string label, long total, bool enabled, bool terminal)
    : label_(std::move(label)), total_(total), enabled_(enabled && total > 0 && (terminal || ::isatty(2) == 1)) {}

Progress::~Progress() {
    if (enabled_ && last_draw_ >= 0.0) std::fprintf(stderr, "\r\033[K");
}

std::string Progress::bar(const std::string& label, long done, long total, double elapsed, int width) {
    const double f = total > 0 ? double(done) / double(total) : 1.0;
    const int full = int(f * width + 1e-9);
    std::string s = label + " [" + std::string(std::size_t(full), '#') + std::string(std::size_t(width - full), ' ') + "] ";
    char buf[96];
    if (done > 0 && done < total)
        std::snprintf(buf, sizeof buf, "%3d%%  %.1f s, ~%.1f s left", int(100 * f), elapsed,
                      elapsed * double(total - done) / double(done));
    else
        std::snprintf(buf, sizeof buf, "%3d%%  %.1f s", int(100 * f), elapsed);
    return s + buf;
}

void Progress::tick(long units) {
    const long d = done_ += units;
    if (!enabled_ || !draw_.try_lock()) return;
    const double now = timer_.seconds();
    if (now - last_draw_ >= 0.1 || d == total_) {
        last_draw_ = now;
        std::fprintf(stderr, "\r%s\033[K", bar(label_, d, total_, now).c_str());
        std::fflush(stderr);
    }
    draw_.unlock();
}

}  // namespace arbor::engine
