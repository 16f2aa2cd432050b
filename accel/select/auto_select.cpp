#include "accel/select/auto_select.h"

#include "accel/util/timer.h"
#include "accel/trace.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <stdexcept>

namespace arbor::accel {

namespace {

std::uint64_t mix(std::uint64_t z) {  // splitmix64 finalizer
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
float u01(std::uint64_t seed, std::uint64_t i) { return float(mix(seed ^ mix(i)) >> 40) * 0x1p-24f; }

constexpr AccelKind candidates[] = {AccelKind::brute, AccelKind::bvh_median, AccelKind::bvh_sah, AccelKind::lbvh,
                                    AccelKind::kdtree};

/// CPU time of the whole process, ms (all threads).
double process_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// Threads a parallel trace runs on now (the global_control limit, at most the hardware's).
double active_threads() {
    const auto limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    return double(std::max<std::size_t>(1, std::min<std::size_t>(limit, std::size_t(tbb::info::default_concurrency()))));
}

std::string human_ms(double ms) {
    char buf[32];
    if (ms >= 1000.0) std::snprintf(buf, sizeof buf, "%.2f s", ms * 1e-3);
    else std::snprintf(buf, sizeof buf, "%.1f ms", ms);
    return buf;
}

std::string human_count(double n) {
    char buf[32];
    if (n >= 1e9) std::snprintf(buf, sizeof buf, "%.3gG", n * 1e-9);
    else if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.3gM", n * 1e-6);
    else if (n >= 1e3) std::snprintf(buf, sizeof buf, "%.3gk", n * 1e-3);
    else std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}

}  // namespace

std::vector<Ray> rays_into_bounds(const Bounds& b, std::size_t n, std::uint64_t seed) {
    std::vector<Ray> rays(n);
    if (b.empty()) return rays;
    const Vec3f c = b.center(), ext = b.extent();
    const float r = std::max(0.5f * simd::length(ext), 1e-6f);
    for (std::size_t i = 0; i < n; ++i) {
        const float z = 1.0f - 2.0f * u01(seed, 5 * i), phi = 6.2831853f * u01(seed, 5 * i + 1);
        const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const Vec3f on_sphere = c + Vec3f{s * std::cos(phi), s * std::sin(phi), z} * (2.0f * r);
        const Vec3f target{b.lo.x + u01(seed, 5 * i + 2) * ext.x, b.lo.y + u01(seed, 5 * i + 3) * ext.y,
                           b.lo.z + u01(seed, 5 * i + 4) * ext.z};
        rays[i] = {on_sphere, 0.0f, target - on_sphere, std::numeric_limits<float>::infinity()};
    }
    return rays;
}

struct AutoSelector::Impl {
    struct Candidate {
        AccelKind kind;
        std::unique_ptr<Accel> whole, sub;  // built on the whole scene / on the subset
        double whole_ms = -1.0, sub_ms = -1.0;
        bool taken = false;  // whole handed over by take_built
    };
    /// One timing of a structure on the sample.
    struct Timed {
        double ns = 0.0;
        TracePath path = TracePath::scalar;
    };

    TriangleView tris, subset;
    AutoConfig cfg;
    std::size_t n = 0, m = 0;  // triangles of the scene and of the subset (0: calibrated whole)
    std::vector<std::uint32_t> subset_indices;
    Bounds bounds;
    std::vector<Candidate> cands;
    std::size_t anchor = 0;   // index into cands
    bool calibrated = false;  // every candidate built (whole or on the subset)
    double spent_ms = 0.0;
    std::size_t last_sample = 0;  // rays of the last predict()
    std::size_t refined = 0;      // candidates built whole by refine()

    /// Trace time per ray, ns, of each structure on its fastest path: each SIMD path it has
    /// (packet, single; the scalar path where it has none) is timed, and the faster one is the
    /// structure's path, the one a trace with --accel auto then runs. A time is the fastest of
    /// cfg.repeats timings of `rays` (process CPU time / threads), the repeats of all (structure,
    /// path) pairs interleaved so that a burst of other work does not hit one alone. One timing
    /// traces the sample as often as it takes to fill cfg.min_timed_ms.
    std::vector<Timed> time(const std::vector<const Accel*>& accels, std::span<const Ray> rays, bool any_hit) const {
        std::vector<Timed> out(accels.size());
        if (rays.empty()) {
            for (std::size_t i = 0; i < accels.size(); ++i)
                out[i].path = choose_path(accels[i]->offer(), rays, {any_hit ? Query::any : Query::closest}).path;
            return out;
        }
        struct Config {
            std::size_t accel;
            TracePath path;
            double ns = std::numeric_limits<double>::infinity();
        };
        std::vector<Config> configs;
        for (std::size_t i = 0; i < accels.size(); ++i) {
            const std::size_t before = configs.size();
            for (const TracePath p : {TracePath::packet, TracePath::single})
                if (accels[i]->offer().has(p)) configs.push_back({i, p});
            if (configs.size() == before)
                configs.push_back({i, choose_path(accels[i]->offer(), rays, {any_hit ? Query::any : Query::closest}).path});
        }
        std::vector<Hit> hits(rays.size());
        const double threads = active_threads();
        for (int r = 0; r < std::max(cfg.repeats, 1); ++r)
            for (Config& c : configs) {
                const Timer t;
                const double cpu0 = process_cpu_ms();
                std::size_t traced = 0;
                do {
                    trace_parallel(*accels[c.accel], rays, hits, any_hit ? Query::any : Query::closest, c.path);
                    traced += rays.size();
                } while (t.ms() < cfg.min_timed_ms);
                // CPU time / threads: the wall time on an idle machine, not the time other jobs
                // held the cores (the same on an idle machine, far steadier on a shared one).
                const double ms = (process_cpu_ms() - cpu0) / threads;
                c.ns = std::min(c.ns, ms * 1e6 / double(traced));
            }
        for (std::size_t i = 0; i < accels.size(); ++i) out[i].ns = std::numeric_limits<double>::infinity();
        for (const Config& c : configs)  // the first of equal times: deterministic order
            if (c.ns < out[c.accel].ns) out[c.accel] = {c.ns, c.path};
        return out;
    }

    /// Builds `kind` over `view`, timed; a build faster than cfg.rebuild_below_ms is built once
    /// more and the faster time kept (the first build of a scene pays for cold caches and page
    /// faults, and one short timing on a shared machine may have waited a whole scheduler slice).
    std::unique_ptr<Accel> timed_build(AccelKind kind, const TriangleView& view, double& ms) const {
        const Timer t;
        std::unique_ptr<Accel> a = make_accel(kind, view, cfg.build);
        ms = t.ms();
        if (ms < cfg.rebuild_below_ms) {
            a.reset();
            const Timer t2;
            a = make_accel(kind, view, cfg.build);
            ms = std::min(ms, t2.ms());
        }
        return a;
    }

    /// Builds every candidate but the anchor (whole, or on the subset), and the anchor on the subset.
    void calibrate() {
        if (calibrated) return;
        calibrated = true;
        const AccelKind anchor_kind = cands[anchor].kind;
        std::vector<Candidate> kept;
        for (auto& c : cands) {
            try {
                if (m) c.sub = timed_build(c.kind, subset, c.sub_ms);
                else if (!c.whole) c.whole = timed_build(c.kind, tris, c.whole_ms);
            } catch (const std::invalid_argument&) {
                if (c.kind != anchor_kind) continue;  // not in this build
            }
            kept.push_back(std::move(c));
        }
        cands = std::move(kept);
        for (std::size_t i = 0; i < cands.size(); ++i)
            if (cands[i].kind == anchor_kind) anchor = i;
    }

    /// The calibration rays: the sample, or runs of consecutive rays spread over a longer one.
    std::vector<Ray> sample_rays(std::span<const Ray> sample) const {
        std::vector<Ray> rays;
        if (sample.empty()) return rays_into_bounds(bounds, cfg.sample_rays, cfg.seed);
        if (sample.size() <= cfg.sample_rays) return {sample.begin(), sample.end()};
        // Runs of consecutive rays spread over the sample: rays from one image tile stay together,
        // so coherent rays are timed as coherent (a strided pick would make them incoherent).
        const std::size_t run = std::clamp<std::size_t>(cfg.sample_rays, 1, 256);  // < sample.size()
        const std::size_t runs = (cfg.sample_rays + run - 1) / run;
        for (std::size_t r = 0; r < runs; ++r) {
            const std::size_t first = r * (sample.size() - run) / std::max<std::size_t>(runs - 1, 1);
            rays.insert(rays.end(), sample.begin() + std::ptrdiff_t(first), sample.begin() + std::ptrdiff_t(first + run));
        }
        return rays;
    }
};

AutoSelector::AutoSelector(const TriangleView& tris, const AutoConfig& cfg) : impl_(std::make_unique<Impl>()) {
    const Timer timer;
    Impl& s = *impl_;
    s.tris = tris;
    s.cfg = cfg;
    s.n = tris.triangle_count();
    for (std::size_t t = 0; t < s.n; ++t)
        if (tris.triangle_is_finite(t)) s.bounds.grow(tris.triangle_bounds(t));

    if (s.n > cfg.full_triangles && cfg.full_triangles > 0) {
        // Stratified random subset: one triangle from each of m equal runs of the numbering.
        s.m = cfg.full_triangles;
        s.subset_indices.reserve(3 * s.m);
        for (std::size_t j = 0; j < s.m; ++j) {
            const double pos = (double(j) + double(u01(cfg.seed ^ 0xABCDull, j))) * double(s.n) / double(s.m);
            const std::size_t t = std::min(s.n - 1, std::size_t(pos));
            for (int k = 0; k < 3; ++k) s.subset_indices.push_back(tris.indices[3 * t + std::size_t(k)]);
        }
        s.subset = {tris.x, tris.y, tris.z, s.subset_indices};
    }
    for (const AccelKind k : candidates)
        if (k != AccelKind::brute || s.n <= cfg.brute_triangles) s.cands.push_back({k, nullptr, nullptr});

    // The anchor, built whole now: lbvh (the cheapest build), else the first candidate that builds.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < s.cands.size(); ++i)
        if (s.cands[i].kind == AccelKind::lbvh) order.push_back(i);
    for (std::size_t i = 0; i < s.cands.size(); ++i)
        if (s.cands[i].kind != AccelKind::lbvh) order.push_back(i);
    bool built = false;
    for (const std::size_t i : order) {
        try {
            s.cands[i].whole = s.timed_build(s.cands[i].kind, tris, s.cands[i].whole_ms);
            s.anchor = i;
            built = true;
            break;
        } catch (const std::invalid_argument&) {
        }
    }
    if (!built) throw std::invalid_argument("auto: no acceleration structure can be built");
    s.spent_ms = timer.ms();
}

AutoSelector::~AutoSelector() = default;

double AutoSelector::calibration_ms() const { return impl_->spent_ms; }

std::unique_ptr<Accel> AutoSelector::take_built(AccelKind kind) {
    for (auto& c : impl_->cands)
        if (c.kind == kind && c.whole) {
            c.taken = true;
            return std::move(c.whole);
        }
    return nullptr;
}

AutoChoice AutoSelector::choose_tiny(std::span<const Ray> sample, bool any_hit, double budget) {
    Impl& s = *impl_;
    budget = std::max(budget, 0.0);
    Impl::Candidate& a = s.cands[s.anchor];
    if (!a.whole || a.kind != AccelKind::lbvh || s.n <= s.cfg.brute_triangles) return {};
    // lbvh's trace time for the budget is a small part of its build, and every other build is
    // slower, so no structure can beat lbvh by more than that part.
    const Timer timer;
    const std::vector<Ray> rays = s.sample_rays(sample);
    const Impl::Timed t = s.time({a.whole.get()}, rays, any_hit).front();
    s.spent_ms += timer.ms();
    const double trace_ms = budget * t.ns * 1e-6;
    if (trace_ms > s.cfg.tiny_trace_fraction * a.whole_ms) return {};
    AutoChoice out;
    out.kind = a.kind;
    out.path = t.path;
    out.predictions = {{a.kind, a.whole_ms, t.ns, a.whole_ms + trace_ms, true, t.path}};
    out.calibration_ms = s.spent_ms;
    out.reason = std::string(to_string(a.kind)) + ": " + std::string(to_string(t.path)) + " path, tiny budget: " +
                 human_count(budget) + " rays trace in " + human_ms(trace_ms) + " <= " +
                 std::to_string(int(std::lround(100 * s.cfg.tiny_trace_fraction))) + "% of its build (" +
                 human_ms(a.whole_ms) + "), the cheapest; the others not calibrated; " + std::to_string(rays.size()) +
                 " rays, " + human_ms(s.spent_ms);
    return out;
}

AutoChoice AutoSelector::choose(std::span<const Ray> sample, bool any_hit, double budget) {
    AutoChoice tiny = choose_tiny(sample, any_hit, budget);
    if (!tiny.predictions.empty()) return tiny;
    return pick(refine(predict(sample, any_hit), sample, any_hit, budget), budget);
}

std::vector<AutoPrediction> AutoSelector::predict(std::span<const Ray> sample, bool any_hit) {
    const Timer timer;
    Impl& s = *impl_;
    s.calibrate();
    const std::vector<Ray> rays = s.sample_rays(sample);
    s.last_sample = rays.size();

    // Every structure built whole is timed whole; in subset mode, every candidate without a whole
    // build is timed on the subset, and so is the anchor (the ratio's denominator).
    std::vector<const Accel*> timed;
    std::vector<std::ptrdiff_t> whole_at(s.cands.size(), -1), sub_at(s.cands.size(), -1);
    for (std::size_t i = 0; i < s.cands.size(); ++i) {
        const auto& c = s.cands[i];
        if (c.whole) whole_at[i] = std::ptrdiff_t(timed.size()), timed.push_back(c.whole.get());
        if (c.sub && (!c.whole || i == s.anchor)) sub_at[i] = std::ptrdiff_t(timed.size()), timed.push_back(c.sub.get());
    }
    const std::vector<Impl::Timed> ts = s.time(timed, rays, any_hit);

    std::vector<AutoPrediction> out;
    const double inf = std::numeric_limits<double>::infinity();
    const double anchor_whole = whole_at[s.anchor] >= 0 ? ts[std::size_t(whole_at[s.anchor])].ns : inf;
    const double anchor_sub = sub_at[s.anchor] >= 0 ? ts[std::size_t(sub_at[s.anchor])].ns : 0.0;
    const Impl::Candidate& a = s.cands[s.anchor];
    // Build time: subset time x N/m (x log N / log m for top-down builders), corrected by how
    // the anchor's own build scaled from the subset to the whole scene (caches, threads).
    const double ratio = s.m ? double(s.n) / double(s.m) : 1.0;
    const double correction = s.m && a.sub_ms > 0 && a.whole_ms > 0 ? a.whole_ms / (a.sub_ms * ratio) : 1.0;
    const double log_ratio = s.m ? std::log2(double(s.n)) / std::log2(double(s.m)) : 1.0;
    for (std::size_t i = 0; i < s.cands.size(); ++i) {
        const auto& c = s.cands[i];
        AutoPrediction p{c.kind, 0.0, inf, 0.0, c.whole != nullptr, TracePath::scalar};
        if (whole_at[i] >= 0) {
            p.build_ms = c.whole_ms;
            p.ns_per_ray = ts[std::size_t(whole_at[i])].ns;
            p.path = ts[std::size_t(whole_at[i])].path;
        } else if (sub_at[i] >= 0) {
            p.build_ms = c.sub_ms * ratio * correction * (c.kind == AccelKind::lbvh ? 1.0 : log_ratio);
            const double sub = ts[std::size_t(sub_at[i])].ns;
            p.ns_per_ray = anchor_sub > 0 && std::isfinite(anchor_whole) ? anchor_whole * sub / anchor_sub : sub;
            p.path = ts[std::size_t(sub_at[i])].path;
        } else {
            p.build_ms = c.whole_ms;  // taken: can no longer be timed
        }
        out.push_back(p);
    }
    s.spent_ms += timer.ms();
    return out;
}

std::vector<AutoPrediction> AutoSelector::refine(std::vector<AutoPrediction> predictions, std::span<const Ray> sample,
                                                 bool any_hit, double budget) {
    Impl& s = *impl_;
    if (!s.m || predictions.empty()) return predictions;
    const Timer timer;
    auto total = [&](const AutoPrediction& p) { return p.build_ms + std::max(budget, 0.0) * p.ns_per_ray * 1e-6; };
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : predictions) best = std::min(best, total(p));
    bool built = false;
    for (const auto& p : predictions) {
        if (p.built_whole || total(p) > (1.0 + s.cfg.refine_margin) * best || p.build_ms > s.cfg.refine_fraction * best)
            continue;
        for (auto& c : s.cands) {
            if (c.kind != p.kind || c.whole || c.taken) continue;
            c.whole = s.timed_build(c.kind, s.tris, c.whole_ms);
            built = true;
            ++s.refined;
        }
    }
    s.spent_ms += timer.ms();
    return built ? predict(sample, any_hit) : predictions;
}

AutoChoice AutoSelector::pick(std::vector<AutoPrediction> predictions, double budget) const {
    const Impl& s = *impl_;
    budget = std::max(budget, 0.0);
    AutoChoice out;
    out.predictions = std::move(predictions);
    if (out.predictions.empty()) throw std::invalid_argument("auto: no predictions to pick from");
    for (auto& p : out.predictions) p.total_ms = p.build_ms + budget * p.ns_per_ray * 1e-6;
    std::stable_sort(out.predictions.begin(), out.predictions.end(),
                     [](const AutoPrediction& a, const AutoPrediction& b) { return a.total_ms < b.total_ms; });
    // The tie rule: totals within cfg.tie of the smallest cannot be told apart by the calibration.
    // When the build is most of the total, the cheapest build among them; else bvh-sah when tied.
    const AutoPrediction& first = out.predictions.front();
    const AutoPrediction* chosen = &first;
    std::string tie_note;
    std::size_t tied = 0;
    for (const auto& p : out.predictions) tied += p.total_ms <= first.total_ms * (1.0 + s.cfg.tie);
    if (tied > 1) {
        const bool build_bound = first.build_ms >= 0.5 * first.total_ms;
        for (std::size_t i = 0; i < tied; ++i) {
            const AutoPrediction& p = out.predictions[i];
            if (build_bound ? p.build_ms < chosen->build_ms : p.kind == AccelKind::bvh_sah) chosen = &p;
        }
        if (chosen != &first)
            tie_note = std::string("; tie within ") + std::to_string(int(std::lround(100 * s.cfg.tie))) + "% with " +
                       std::string(to_string(first.kind)) + ": " + (build_bound ? "cheaper build" : "the robust tree");
    }
    const AutoPrediction best = *chosen;
    out.kind = best.kind;
    out.path = best.path;
    out.calibration_ms = s.spent_ms;

    std::string r = std::string(to_string(best.kind)) + ": " + std::string(to_string(best.path)) + " path, predicted " +
                    human_ms(best.total_ms) + " for " + human_count(budget) + " rays (build " + human_ms(best.build_ms) +
                    " + " + human_count(best.ns_per_ray > 0 ? 1e3 / best.ns_per_ray * 1e6 : 0.0) + " rays/s)";
    for (const auto& next : out.predictions)
        if (next.kind != best.kind) {
            r += "; next " + std::string(to_string(next.kind)) + " " + human_ms(next.total_ms);
            break;
        }
    r += tie_note;
    r += s.m ? "; calibrated on " + human_count(double(s.m)) + " of " + human_count(double(s.n)) + " triangles + whole " +
                   std::string(to_string(s.cands[s.anchor].kind)) +
                   (s.refined ? " and " + std::to_string(s.refined) + " refined" : std::string())
             : "; calibrated on all " + human_count(double(s.n)) + " triangles";
    r += ", " + std::to_string(s.last_sample) + " rays, " + human_ms(s.spent_ms);
    out.reason = r;
    return out;
}

AccelPick pick_accel(AccelKind kind, const TriangleView& tris, const AutoWork& work) {
    AccelPick out;
    out.kind = kind;
    if (kind != AccelKind::automatic) return out;
    AutoConfig cfg;
    cfg.build = work.build;
    AutoSelector selector(tris, cfg);
    AutoChoice choice = selector.choose(work.sample, work.query == Query::any, work.budget);
    out.kind = choice.kind;
    out.path = choice.path;
    out.reason = std::move(choice.reason);
    out.built = selector.take_built(choice.kind);
    out.calibration_ms = choice.calibration_ms;
    return out;
}

}  // namespace arbor::accel
