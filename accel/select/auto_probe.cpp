#include "accel/select/auto_probe.h"

#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"

#include <algorithm>
#include <ctime>
#include <limits>

namespace arbor::accel {

double process_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double thread_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

ProbeResult run_probe(const TriangleView& tris, const BuildConfig& cfg, const std::vector<AccelKind>& structures,
                      const std::vector<ProbeConfig>& configs, const std::vector<ProbeGroup>& groups, int rounds,
                      double min_timing_ms, double threads) {
    ProbeResult out;
    for (const AccelKind k : structures) {
        const Timer t;
        out.built.push_back(make_accel(k, tris, cfg));
        out.build_ms.push_back(t.ms());
    }
    const double inf = std::numeric_limits<double>::infinity();
    out.ns.assign(configs.size(), std::vector<double>(groups.size(), inf));
    std::size_t longest = 0;
    for (const ProbeGroup& g : groups) longest = std::max(longest, g.rays.size());
    std::vector<Hit> hits(longest);
    threads = std::max(threads, 1.0);
    for (int r = 0; r < std::max(rounds, 1); ++r)
        for (std::size_t c = 0; c < configs.size(); ++c)
            for (std::size_t g = 0; g < groups.size(); ++g) {
                const ProbeGroup& group = groups[g];
                if (group.rays.empty()) continue;
                const Accel& a = *out.built[configs[c].structure];
                const TraceRequest req{group.query, configs[c].group_paths[g]};
                const std::span<Hit> h(hits.data(), group.rays.size());
                const Timer wall;
                const double cpu0 = thread_cpu_ms();
                std::size_t traced = 0;
                do {
                    a.trace(group.rays, h, req);
                    traced += group.rays.size();
                } while (wall.ms() < min_timing_ms);
                const double ns = (thread_cpu_ms() - cpu0) / threads * 1e6 / double(traced);
                out.ns[c][g] = std::min(out.ns[c][g], ns);
            }
    return out;
}

}  // namespace arbor::accel
