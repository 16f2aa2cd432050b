#include "accel/select/auto_select.h"

#include "accel/select/auto_model.h"
#include "accel/select/auto_probe.h"
#include "accel/select/path_policy.h"
#include "accel/util/splitmix64.h"
#include "accel/util/timer.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace arbor::accel {

namespace {

float u01(std::uint64_t seed, std::uint64_t i) { return unit_float24(splitmix64(seed ^ splitmix64(i))); }

std::string human_ms(double ms) {
    char buf[32];
    if (ms >= 1000.0) std::snprintf(buf, sizeof buf, "%.2f s", ms * 1e-3);
    else if (ms >= 10.0) std::snprintf(buf, sizeof buf, "%.0f ms", ms);
    else if (ms >= 0.1) std::snprintf(buf, sizeof buf, "%.2f ms", ms);
    else std::snprintf(buf, sizeof buf, "%.3f ms", ms);
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

std::string percent(double f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f%%", 100.0 * f);
    return buf;
}

/// A configuration being weighed: the candidate plus the path and predicted ns of each group.
struct Weighed {
    AutoCandidate c;
    std::vector<TracePath> paths;  // per group
    std::vector<double> ns;        // per group, predicted
};

std::string config_name(const AutoCandidate& c) {
    std::string s(to_string(c.kind));
    if (c.path != TracePath::best) s.append("/").append(to_string(c.path));
    return s;
}

/// The reason's start: "bvh-sah: packet path," (the path left out when the groups' paths are fixed).
std::string pick_words(const AutoCandidate& c) {
    std::string s(to_string(c.kind));
    s += ":";
    if (c.path != TracePath::best) s.append(" ").append(to_string(c.path)).append(" path,");
    return s;
}

/// "lbvh/single 2.05 s (build 8.0 ms + 170 ns/ray)": a candidate's total and its parts; ns/ray is
/// the trace time over all the job's rays.
std::string describe(const AutoCandidate& c, double rays) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.0f ns/ray", rays > 0 ? c.trace_ms * 1e6 / rays : 0.0);
    return config_name(c) + " " + human_ms(c.total_ms) + " (build " + human_ms(c.build_ms) + " + " + buf + ")";
}

/// Every structure of the model that this build config can run the job on, with each free path.
std::vector<Weighed> predict_all(const AutoModel& model, const SceneShape& scene, const std::vector<RayGroup>& groups,
                                 const BuildConfig& build, double threads) {
    std::vector<Weighed> out;
    bool free = false;
    for (const RayGroup& g : groups) free |= g.shape.path == TracePath::best && g.shape.hint == RayHint::unknown;
    for (const AccelKind kind : model.structures()) {
        const PathOffer offer = expected_offer(kind, build);
        std::vector<TracePath> choices{TracePath::best};
        if (free) {
            choices.clear();
            for (const TracePath p : {TracePath::packet, TracePath::single})
                if (offer.has(p)) choices.push_back(p);
            if (choices.empty() && offer.has(TracePath::scalar)) choices.push_back(TracePath::scalar);
        }
        for (const TracePath choice : choices) {
            Weighed w;
            w.c.kind = kind;
            w.c.path = free ? choice : TracePath::best;
            bool ok = true;
            for (const RayGroup& g : groups) {
                TracePath p = choice;
                if (!(g.shape.path == TracePath::best && g.shape.hint == RayHint::unknown))
                    p = choose_path(offer, {}, {g.shape.query, g.shape.path, g.shape.hint}).path;
                if (!model.has(kind, p) || !offer.runs(p, g.shape.query)) {
                    ok = false;
                    break;
                }
                const double ns = model.ns_per_ray(kind, p, scene, g.shape, threads);
                w.paths.push_back(p);
                w.ns.push_back(ns);
                w.c.trace_ms += g.shape.rays * ns * 1e-6;
            }
            if (!ok) continue;
            w.c.build_ms = model.build_ms(kind, scene, threads);
            w.c.total_ms = w.c.build_ms + w.c.trace_ms;
            out.push_back(std::move(w));
        }
    }
    // Smallest total first; equal totals keep the model's order (deterministic).
    std::stable_sort(out.begin(), out.end(), [](const Weighed& a, const Weighed& b) { return a.c.total_ms < b.c.total_ms; });
    return out;
}

/// At most `n` consecutive-run samples of `rays`: runs of 256 consecutive rays spread evenly over
/// them (rays of one image tile stay together, so coherent rays are timed as coherent).
std::span<const Ray> cut_sample(std::span<const Ray> rays, std::size_t n, std::vector<Ray>& store) {
    if (rays.size() <= n) return rays;
    const std::size_t run = std::min<std::size_t>(256, n), runs = std::max<std::size_t>(n / run, 1);
    store.clear();
    for (std::size_t r = 0; r < runs; ++r) {
        const std::size_t first = runs > 1 ? r * (rays.size() - run) / (runs - 1) : 0;
        store.insert(store.end(), rays.begin() + std::ptrdiff_t(first), rays.begin() + std::ptrdiff_t(first + run));
    }
    return store;
}

}  // namespace

int active_trace_threads() {
    const auto limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    const int arena = tbb::this_task_arena::max_concurrency();
    return std::max(1, std::min(int(std::min<std::size_t>(limit, 1u << 20)), arena));
}

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

AutoJob trace_job(const TriangleView& tris, std::span<const Ray> sample, double count, Query query, TracePath path,
                  const BuildConfig& build) {
    AutoJob job;
    job.tris = tris;
    job.build = build;
    RayGroup g;
    g.sample = sample;
    g.shape.rays = count;
    g.shape.query = query;
    g.shape.path = path;
    job.groups.push_back(g);
    return job;
}

AccelPick pick_accel(AccelKind kind, const AutoJob& job) {
    AccelPick out;
    out.kind = kind;
    if (kind != AccelKind::automatic) return out;
    // (Asked before the timer starts: the first TBB call of a process starts the library, a cost the
    // job's first parallel build or trace pays anyway.)
    const double threads = job.threads > 0 ? double(job.threads) : double(active_trace_threads());
    const Timer timer;
    const AutoModel& model = job.model ? *job.model : builtin_auto_model();
    const SceneShape scene = scene_shape(job.tris);
    const float diagonal = simd::length(scene.bounds.extent());

    // The groups with their shapes measured where the caller gave rays but no coherence.
    std::vector<RayGroup> groups = job.groups;
    std::vector<Ray> default_rays;
    if (groups.empty()) {
        default_rays = rays_into_bounds(scene.bounds, 4096, 1);
        RayGroup g;
        g.sample = default_rays;
        g.shape.rays = AutoJob::default_rays;
        groups.push_back(g);
    }
    double rays = 0.0;
    for (RayGroup& g : groups) {
        if (g.shape.coherent < 0.0 || g.shape.together < 0.0) {
            const RayShape s = ray_shape(g.sample, g.shape.rays, g.shape.query, diagonal);
            if (g.shape.coherent < 0.0) g.shape.coherent = s.coherent;
            if (g.shape.together < 0.0) g.shape.together = s.together;
        }
        rays += g.shape.rays;
    }

    std::vector<Weighed> all = predict_all(model, scene, groups, job.build, threads);
    if (all.empty()) throw std::invalid_argument("auto: no structure of the cost model can run this job with these build settings");
    const Weighed& first = all.front();
    const double margin = model.margin();
    std::vector<std::size_t> contenders;  // indices into all
    for (std::size_t i = 0; i < all.size(); ++i)
        if (all[i].c.total_ms <= first.c.total_ms * (1.0 + margin)) contenders.push_back(i);

    // The model's own decision: its best prediction, or the preferred structure's (the default's)
    // best configuration when that is predicted within the model's prefer_share (and margin) of it:
    // the model's errors are ~19% in ratio, and what it misjudges most is a cheap build's trace
    // penalty (auto_model.h, perf/model/fit_auto_model.py).
    const Weighed* lead = &first;
    const double prefer = std::min(model.prefer_share(), margin);
    if (prefer > 0.0)
        for (const Weighed& w : all)
            if (w.c.kind == model.preferred()) {
                if (w.c.total_ms <= first.c.total_ms * (1.0 + prefer)) lead = &w;
                break;
            }
    const std::string job_line = " for " + human_count(rays) + " rays";
    const std::string preferred =
        lead != &first ? ", preferred within " + percent(prefer) + " of the best prediction" : std::string();
    // "; next CONFIG, +X%": the best configuration other than `ref` (of another structure, or the
    // other path), against it.
    auto next_after = [&](const Weighed* ref) {
        for (const Weighed& w : all)
            if (&w != ref) {
                const double d = w.c.total_ms / ref->c.total_ms - 1.0;
                return "; next " + describe(w.c, rays) + ", " + (d >= 0.0 ? "+" : "-") + percent(std::abs(d));
            }
        return std::string();
    };
    const std::string next = next_after(lead);
    const std::string margin_text = percent(margin);
    auto finish_model = [&](const std::string& why) {
        out.kind = lead->c.kind;
        out.path = lead->c.path;
        for (const Weighed& w : all) out.candidates.push_back(w.c);
        out.auto_ms = timer.ms();
        out.own_ms = out.auto_ms;
        out.reason = pick_words(lead->c) + " model: predicted " + describe(lead->c, rays) + job_line + preferred +
                     next + why + "; auto " + human_ms(out.auto_ms);
        return std::move(out);
    };
    if (contenders.size() == 1) return finish_model(" (outside the model's " + margin_text + " margin)");
    // A probe times both paths of each structure it builds: the model's packet-over-single ratios are
    // among its largest errors (on its own training rows it rates packets 1.25-1.45x too well against
    // single rays on the tiny scene's random rays, bunny's primary and shadow rays, grass's primary
    // rays: perf/results/auto-2026-12-03.md), and the other path of a structure the probe builds
    // anyway costs one more sample timing.
    const std::size_t within_margin = contenders.size();
    for (std::size_t c = 0; c < within_margin; ++c)
        for (std::size_t i = 0; i < all.size(); ++i)
            if (all[i].c.kind == all[contenders[c]].c.kind &&
                std::find(contenders.begin(), contenders.end(), i) == contenders.end())
                contenders.push_back(i);
    const std::string within = " (within the model's " + margin_text + " margin)";
    if (!job.allow_probe) return finish_model(within + ", probe not allowed");

    // The probe: samples of each group (up to 4096 rays), structures in the order of their best
    // prediction, the costliest builds dropped until the probe fits its cap.
    std::vector<std::vector<Ray>> stores(groups.size());
    std::vector<ProbeGroup> probe_groups(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g)
        probe_groups[g] = {cut_sample(groups[g].sample, 4096, stores[g]), groups[g].shape.query};
    // Two caps: a share of the job, and a share of what the probe can win. The model cannot order
    // its contenders within its margin, so its pick is off by about the margin times the part of
    // the job they do not share: a build that every probed contender needs (all of one structure:
    // the first's, which is never dropped) is paid whatever the probe finds, and two paths of one
    // structure differ in their traces only.
    const double job_cap = job.probe_share * first.c.total_ms;
    auto stake_of = [&](const std::vector<AccelKind>& s) {
        return margin * (first.c.total_ms - (s.size() == 1 ? first.c.build_ms : 0.0));
    };
    auto cap_of = [&](const std::vector<AccelKind>& s) { return std::min(job_cap, job.stake_share * stake_of(s)); };
    const int rounds = 2;
    std::vector<AccelKind> structures;
    for (const std::size_t i : contenders)
        if (std::find(structures.begin(), structures.end(), all[i].c.kind) == structures.end()) structures.push_back(all[i].c.kind);
    auto cost_of = [&](const std::vector<AccelKind>& s) {
        double cost = 0.0;
        for (std::size_t k = 1; k < s.size(); ++k) cost += model.build_ms(s[k], scene, threads);
        for (const std::size_t i : contenders) {
            if (std::find(s.begin(), s.end(), all[i].c.kind) == s.end()) continue;
            for (std::size_t g = 0; g < groups.size(); ++g)
                if (!probe_groups[g].rays.empty())
                    cost += rounds * std::max(job.min_timing_ms,
                                              double(probe_groups[g].rays.size()) * all[i].ns[g] * threads * 1e-6);
        }
        return cost;
    };
    double cost = cost_of(structures);
    while (cost > cap_of(structures) && structures.size() > 1) {
        auto costliest = std::max_element(structures.begin() + 1, structures.end(), [&](AccelKind a, AccelKind b) {
            return model.build_ms(a, scene, threads) < model.build_ms(b, scene, threads);
        });
        structures.erase(costliest);
        cost = cost_of(structures);
    }
    std::size_t probed_configs = 0;
    for (const std::size_t i : contenders)
        probed_configs += std::find(structures.begin(), structures.end(), all[i].c.kind) != structures.end();
    bool sampled = false;
    for (const ProbeGroup& g : probe_groups) sampled |= !g.rays.empty();
    const double cap = cap_of(structures), stake = stake_of(structures), stake_cap = job.stake_share * stake;
    if (cost > cap || probed_configs < 2 || !sampled)
        return finish_model(within + ", no probe: " +
                            (!sampled ? std::string("no rays to time")
                             : job_cap <= stake_cap
                                 ? "it would cost " + human_ms(cost) + ", more than " + percent(job.probe_share) +
                                       " of the job (" + human_ms(cap) + ")"
                                 : "it would cost " + human_ms(cost) + ", more than " + percent(job.stake_share) +
                                       " of what it can win (" + human_ms(cap) + " of " + human_ms(stake) + ": the margin x " +
                                       (structures.size() == 1 ? "the trace" : "the job") + ")"));

    std::vector<ProbeConfig> configs;
    std::vector<std::size_t> config_of;  // index into all
    for (const std::size_t i : contenders) {
        const auto s = std::find(structures.begin(), structures.end(), all[i].c.kind);
        if (s == structures.end()) continue;
        configs.push_back({std::size_t(s - structures.begin()), all[i].paths});
        config_of.push_back(i);
    }
    ProbeResult probe = run_probe(job.tris, job.build, structures, configs, probe_groups, rounds, job.min_timing_ms, threads);

    // Measured totals: the probe's build, and per group its measured ns (unsampled groups: the
    // prediction scaled by the configuration's mean measured/predicted ratio).
    std::vector<AutoCandidate> measured;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const Weighed& w = all[config_of[c]];
        double log_ratio = 0.0;
        int n = 0;
        for (std::size_t g = 0; g < groups.size(); ++g)
            if (!probe_groups[g].rays.empty()) log_ratio += std::log(probe.ns[c][g] / w.ns[g]), ++n;
        const double scale = n ? std::exp(log_ratio / n) : 1.0;
        AutoCandidate m = w.c;
        m.probed = true;
        m.build_ms = probe.build_ms[configs[c].structure];
        m.trace_ms = 0.0;
        for (std::size_t g = 0; g < groups.size(); ++g)
            m.trace_ms += groups[g].shape.rays * (probe_groups[g].rays.empty() ? w.ns[g] * scale : probe.ns[c][g]) * 1e-6;
        m.total_ms = m.build_ms + m.trace_ms;
        measured.push_back(m);
    }
    std::stable_sort(measured.begin(), measured.end(),
                     [](const AutoCandidate& a, const AutoCandidate& b) { return a.total_ms < b.total_ms; });
    const AutoCandidate& pick = measured.front();
    out.kind = pick.kind;
    out.path = pick.path;
    out.probed = true;
    const auto s = std::find(structures.begin(), structures.end(), pick.kind);
    out.built = std::move(probe.built[std::size_t(s - structures.begin())]);
    out.candidates = measured;
    for (const Weighed& w : all)
        if (std::none_of(measured.begin(), measured.end(), [&](const AutoCandidate& m) { return m.kind == w.c.kind && m.path == w.c.path; }))
            out.candidates.push_back(w.c);
    std::size_t sample_rays = 0;
    for (const ProbeGroup& g : probe_groups) sample_rays += g.rays.size();
    out.auto_ms = timer.ms();
    const double handed_ms = out.built ? probe.build_ms[std::size_t(s - structures.begin())] : 0.0;
    out.own_ms = std::max(0.0, out.auto_ms - handed_ms);
    std::string r = pick_words(pick) + " probe: " + describe(pick, rays);
    for (std::size_t i = 1; i < measured.size(); ++i) r += (i == 1 ? "; next " : ", ") + describe(measured[i], rays);
    r += " (" + std::to_string(sample_rays) + " rays timed" + job_line + "); the model had " + describe(first.c, rays) +
         next_after(&first) + within + "; auto " + human_ms(out.own_ms) + " (" + percent(out.own_ms / (pick.total_ms + out.own_ms)) +
         " of the job)" + (out.built ? " + the pick's build " + human_ms(handed_ms) + ", handed over" : "");
    out.reason = std::move(r);
    return out;
}

}  // namespace arbor::accel
