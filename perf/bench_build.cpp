#include "perf/bench_build.h"

#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "engine/error.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace arbor::perf {

std::size_t Built::memory_bytes() const {
    if (accel) return accel->stats().memory_bytes;
#ifdef ARBOR_HAVE_EMBREE
    if (peer) return peer->memory_bytes();
#endif
    return 0;
}

void TraceConfig::trace(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, accel::Query q,
                        bool coherent) const {
    if (built->accel) {
        accel::trace_parallel(*built->accel, rays, hits, q, arbor_path);
        return;
    }
#ifdef ARBOR_HAVE_EMBREE
    built->peer->trace_parallel(rays, hits, q, EmbreeCall(embree_call), coherent);
#endif
}

std::vector<accel::AccelKind> bench_structures(const BenchOptions& o) {
    std::vector<accel::AccelKind> kinds;
    for (const std::string& name : o.structures) {
        const auto k = accel::parse_accel_kind(name);
        if (!k || *k == accel::AccelKind::automatic)
            throw engine::InputError("--structures: unknown structure '" + name + "' (expected " +
                                     accel::accel_kind_names() + " without auto)");
        if (*k == accel::AccelKind::brute) continue;  // --time-brute adds it
        kinds.push_back(*k);
    }
    if (o.time_brute) kinds.insert(kinds.begin(), accel::AccelKind::brute);
    return kinds;
}

std::vector<Built> build_structures(const accel::TriangleView& tris, const BenchOptions& o,
                                    const std::vector<int>& threads, int repeats, std::vector<std::string>& notes,
                                    BuildHistory& history) {
    std::vector<Built> built;
    const std::size_t n = tris.triangle_count();
    for (const accel::AccelKind k : bench_structures(o)) {
        Built b;
        b.name = std::string(accel::to_string(k));
        built.push_back(std::move(b));
    }
#ifdef ARBOR_HAVE_EMBREE
    if (o.embree) {
        std::vector<EmbreeConfig> modes{EmbreeConfig{}};
        if (o.embree_variants) {
            modes.push_back({true, false, false});
            modes.push_back({false, true, false});
        }
        for (const EmbreeConfig& c : modes) {
            Built b;
            b.name = embree_config_name(c);
            b.embree = true;
            b.embree_cfg = c;
            built.push_back(std::move(b));
        }
    }
#endif
    for (Built& b : built) {
        const auto h = history.find(b.name);
        if (h == history.end() || h->second.first >= n || h->second.first < 2) continue;
        const double m = double(h->second.first);
        const double predicted_s =
            h->second.second * 1e-3 * (double(n) / m) * std::log2(double(n)) / std::log2(m);
        if (predicted_s > o.max_build_seconds) {
            notes.push_back(b.name + ": skipped on " + std::to_string(n) + " triangles (one build predicted to take " +
                            std::to_string(int(predicted_s)) + " s > " + std::to_string(int(o.max_build_seconds)) + " s)");
            b.unavailable = true;
        }
    }
    for (const int t : threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
        for (int rep = 0; rep < repeats; ++rep) {
            for (Built& b : built) {
                if (b.unavailable) continue;
#ifdef ARBOR_HAVE_EMBREE
                if (b.is_embree()) {
                    b.peer.reset();
                    b.peer = std::make_unique<EmbreePeer>(tris, b.embree_cfg);
                    b.build_ms[t].push_back(b.peer->build_ms());
                    continue;
                }
#endif
                const auto kind = *accel::parse_accel_kind(b.name);
                b.accel.reset();
                const accel::Timer timer;
                try {
                    b.accel = accel::make_accel(kind, tris);
                } catch (const std::invalid_argument& e) {  // not in this build (yet)
                    notes.push_back(b.name + ": " + e.what());
                    b.unavailable = true;
                    continue;
                }
                b.build_ms[t].push_back(timer.ms());
            }
        }
    }
    std::erase_if(built, [](const Built& b) { return b.unavailable; });
    const int all = *std::max_element(threads.begin(), threads.end());
    for (const Built& b : built) {
        const auto it = b.build_ms.find(all);
        if (it == b.build_ms.end() || it->second.empty()) continue;
        auto& h = history[b.name];
        if (n >= h.first) h = {n, *std::min_element(it->second.begin(), it->second.end())};
    }
    return built;
}

std::vector<TraceConfig> trace_configs(const std::vector<Built>& built) {
    std::vector<TraceConfig> out;
    for (const Built& b : built) {
        if (b.accel) {
            for (const accel::TracePath p : {accel::TracePath::scalar, accel::TracePath::packet, accel::TracePath::single}) {
                if (p != accel::TracePath::scalar && !b.accel->offer().has(p)) continue;
                out.push_back({&b, std::string(accel::to_string(p)), p, 0});
            }
            continue;
        }
#ifdef ARBOR_HAVE_EMBREE
        const bool default_mode = !b.embree_cfg.high_quality && !b.embree_cfg.robust;
        for (const EmbreeCall c : embree_calls()) {
            if (!default_mode && (c == EmbreeCall::packet8 || c == EmbreeCall::packet16)) continue;
            out.push_back({&b, std::string(to_string(c)), accel::TracePath::scalar, int(c)});
        }
#endif
    }
    return out;
}

}  // namespace arbor::perf
