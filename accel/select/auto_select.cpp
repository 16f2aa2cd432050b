#include "accel/select/auto_select.h"

#include "accel/select/auto_decision.h"
#include "accel/select/auto_model.h"
#include "accel/select/auto_reason.h"
#include "accel/select/auto_probe.h"
#include "accel/factory/make_accel.h"
#include "accel/factory/memory_estimate.h"
#include "accel/interface/path_policy.h"
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

namespace {

/// The job's groups with their shapes measured where the caller gave rays but no coherence; with
/// no groups, one of AutoJob::default_rays closest-hit rays into the scene (`default_rays` holds
/// their sample).
std::vector<RayGroup> shaped_groups(const AutoJob& job, const SceneShape& scene, std::vector<Ray>& default_rays) {
    const float diagonal = simd::length(scene.bounds.extent());
    std::vector<RayGroup> groups = job.groups;
    if (groups.empty()) {
        default_rays = rays_into_bounds(scene.bounds, 4096, 1);
        RayGroup g;
        g.sample = default_rays;
        g.shape.rays = AutoJob::default_rays;
        groups.push_back(g);
    }
    for (RayGroup& g : groups) {
        if (g.shape.coherent < 0.0 || g.shape.together < 0.0) {
            const RayShape s = ray_shape(g.sample, g.shape.rays, g.shape.query, diagonal);
            if (g.shape.coherent < 0.0) g.shape.coherent = s.coherent;
            if (g.shape.together < 0.0) g.shape.together = s.together;
        }
    }
    return groups;
}

/// Steps 1 and 2 of the decision (auto_select.h): every configuration predicted, the model's pick,
/// and the contenders within its margin.
ModelDecision decide_by_model(const AutoModel& model, const SceneShape& scene, const std::vector<RayGroup>& groups,
                              const BuildConfig& build, double threads) {
    ModelDecision d;
    for (const RayGroup& g : groups) d.rays += g.shape.rays;
    d.all = predict_all(model, scene, groups, build, threads);
    if (d.all.empty()) throw std::invalid_argument("auto: no structure of the cost model can run this job with these build settings");
    // Under a memory limit, the structures whose build would be refused before it starts are left
    // out (when every one would be, none is: the pick's build then says why).
    if (build.max_memory != 0) {
        std::vector<Weighed> fit;
        for (const Weighed& w : d.all) {
            const std::uint64_t need = build_start_bytes(w.c.kind, scene.triangles, build);
            if (need <= build.max_memory) {
                fit.push_back(w);
                continue;
            }
            const std::string words = std::string(to_string(w.c.kind)) + " " + mib_text(need);
            if (std::find(d.left_out.begin(), d.left_out.end(), words) == d.left_out.end()) d.left_out.push_back(words);
        }
        if (fit.empty()) d.left_out.clear();
        else d.all = std::move(fit);
    }
    const Weighed& first = d.all.front();
    d.margin = model.margin();
    for (std::size_t i = 0; i < d.all.size(); ++i)
        if (d.all[i].c.total_ms <= first.c.total_ms * (1.0 + d.margin)) d.contenders.push_back(i);
    d.within_margin = d.contenders.size();

    // The model's own decision: its best prediction, or the preferred structure's (the default's)
    // best configuration when that is predicted within the model's prefer_share (and margin) of it:
    // the model's errors are ~19% in ratio, and what it misjudges most is a cheap build's trace
    // penalty (auto_model.h, perf/model/fit_auto_model.py).
    d.prefer = std::min(model.prefer_share(), d.margin);
    if (d.prefer > 0.0)
        for (std::size_t i = 0; i < d.all.size(); ++i)
            if (d.all[i].c.kind == model.preferred()) {
                if (d.all[i].c.total_ms <= first.c.total_ms * (1.0 + d.prefer)) d.lead = i;
                break;
            }
    // A probe times both paths of each structure it builds: the model's packet-over-single ratios are
    // among its largest errors (on its own training rows it rates packets 1.25-1.45x too well against
    // single rays on the tiny scene's random rays, bunny's primary and shadow rays, grass's primary
    // rays), and the other path of a structure the probe builds anyway costs one more sample timing.
    for (std::size_t c = 0; c < d.within_margin; ++c)
        for (std::size_t i = 0; i < d.all.size(); ++i)
            if (d.all[i].c.kind == d.all[d.contenders[c]].c.kind &&
                std::find(d.contenders.begin(), d.contenders.end(), i) == d.contenders.end())
                d.contenders.push_back(i);
    return d;
}

/// The probe's samples: up to 4096 rays of each group (`stores` holds the cut ones).
std::vector<ProbeGroup> probe_samples(const std::vector<RayGroup>& groups, std::vector<std::vector<Ray>>& stores) {
    stores.assign(groups.size(), {});
    std::vector<ProbeGroup> out(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) out[g] = {cut_sample(groups[g].sample, 4096, stores[g]), groups[g].shape.query};
    return out;
}

constexpr int probe_rounds = 2;

/// Step 3's plan: the contenders' structures in the order of their best prediction, the costliest
/// builds dropped until the probe fits its caps.
ProbePlan plan_probe(const AutoModel& model, const SceneShape& scene, const ModelDecision& d, const AutoJob& job,
                     const std::vector<ProbeGroup>& probe_groups, double threads) {
    const Weighed& first = d.all.front();
    // Two caps: a share of the job, and a share of what the probe can win. The model cannot order
    // its contenders within its margin, so its pick is off by about the margin times the part of
    // the job they do not share: a build that every probed contender needs (all of one structure:
    // the first's, which is never dropped) is paid whatever the probe finds, and two paths of one
    // structure differ in their traces only.
    ProbePlan plan;
    plan.job_cap = job.probe_share * first.c.total_ms;
    auto stake_of = [&](const std::vector<AccelKind>& s) {
        return d.margin * (first.c.total_ms - (s.size() == 1 ? first.c.build_ms : 0.0));
    };
    auto cap_of = [&](const std::vector<AccelKind>& s) { return std::min(plan.job_cap, job.stake_share * stake_of(s)); };
    std::vector<AccelKind>& structures = plan.structures;
    for (const std::size_t i : d.contenders)
        if (std::find(structures.begin(), structures.end(), d.all[i].c.kind) == structures.end())
            structures.push_back(d.all[i].c.kind);
    auto cost_of = [&](const std::vector<AccelKind>& s) {
        double cost = 0.0;
        for (std::size_t k = 1; k < s.size(); ++k) cost += model.build_ms(s[k], scene, threads);
        for (const std::size_t i : d.contenders) {
            if (std::find(s.begin(), s.end(), d.all[i].c.kind) == s.end()) continue;
            for (std::size_t g = 0; g < probe_groups.size(); ++g)
                if (!probe_groups[g].rays.empty())
                    cost += probe_rounds * std::max(job.min_timing_ms,
                                                    double(probe_groups[g].rays.size()) * d.all[i].ns[g] * threads * 1e-6);
        }
        return cost;
    };
    plan.cost = cost_of(structures);
    while (plan.cost > cap_of(structures) && structures.size() > 1) {
        auto costliest = std::max_element(structures.begin() + 1, structures.end(), [&](AccelKind a, AccelKind b) {
            return model.build_ms(a, scene, threads) < model.build_ms(b, scene, threads);
        });
        structures.erase(costliest);
        plan.cost = cost_of(structures);
    }
    for (const std::size_t i : d.contenders)
        plan.probed_configs += std::find(structures.begin(), structures.end(), d.all[i].c.kind) != structures.end();
    for (const ProbeGroup& g : probe_groups) plan.sampled |= !g.rays.empty();
    plan.cap = cap_of(structures);
    plan.stake = stake_of(structures);
    return plan;
}

/// The probed configurations' measured totals, smallest first: the probe's build, and per group
/// its measured ns (unsampled groups: the prediction scaled by the configuration's mean
/// measured/predicted ratio).
std::vector<AutoCandidate> measured_totals(const ModelDecision& d, const std::vector<RayGroup>& groups,
                                           const std::vector<ProbeGroup>& probe_groups, const std::vector<ProbeConfig>& configs,
                                           const std::vector<std::size_t>& config_of, const ProbeResult& probe) {
    std::vector<AutoCandidate> measured;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const Weighed& w = d.all[config_of[c]];
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
    return measured;
}

}  // namespace

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
    std::vector<Ray> default_rays;
    const std::vector<RayGroup> groups = shaped_groups(job, scene, default_rays);
    const ModelDecision d = decide_by_model(model, scene, groups, job.build, threads);

    auto finish_model = [&](const std::string& why) {
        const AutoCandidate& lead = d.all[d.lead].c;
        out.kind = lead.kind;
        out.path = lead.path;
        for (const Weighed& w : d.all) out.candidates.push_back(w.c);
        out.auto_ms = timer.ms();
        out.own_ms = out.auto_ms;
        out.reason = model_reason(d, why, out.auto_ms);
        return std::move(out);
    };
    if (d.within_margin == 1) return finish_model(outside_margin_words(d));
    if (!job.allow_probe) return finish_model(within_margin_words(d) + ", probe not allowed");
    // (The probe holds its contenders' builds at once: under a limit meant for one build, no probe.)
    if (job.build.max_memory != 0) return finish_model(within_margin_words(d) + ", no probe under max_memory");

    std::vector<std::vector<Ray>> stores;
    const std::vector<ProbeGroup> probe_groups = probe_samples(groups, stores);
    const ProbePlan plan = plan_probe(model, scene, d, job, probe_groups, threads);
    if (!plan.runs()) return finish_model(within_margin_words(d) + ", no probe: " + no_probe_words(plan, job));

    std::vector<ProbeConfig> configs;
    std::vector<std::size_t> config_of;  // index into d.all
    for (const std::size_t i : d.contenders) {
        const auto s = std::find(plan.structures.begin(), plan.structures.end(), d.all[i].c.kind);
        if (s == plan.structures.end()) continue;
        configs.push_back({std::size_t(s - plan.structures.begin()), d.all[i].paths});
        config_of.push_back(i);
    }
    ProbeResult probe =
        run_probe(job.tris, job.build, plan.structures, configs, probe_groups, probe_rounds, job.min_timing_ms, threads);
    const std::vector<AutoCandidate> measured = measured_totals(d, groups, probe_groups, configs, config_of, probe);

    const AutoCandidate& pick = measured.front();
    out.kind = pick.kind;
    out.path = pick.path;
    out.probed = true;
    const std::size_t s = std::size_t(std::find(plan.structures.begin(), plan.structures.end(), pick.kind) - plan.structures.begin());
    out.built = std::move(probe.built[s]);
    out.candidates = measured;
    for (const Weighed& w : d.all)
        if (std::none_of(measured.begin(), measured.end(), [&](const AutoCandidate& m) { return m.kind == w.c.kind && m.path == w.c.path; }))
            out.candidates.push_back(w.c);
    std::size_t sample_rays = 0;
    for (const ProbeGroup& g : probe_groups) sample_rays += g.rays.size();
    out.auto_ms = timer.ms();
    const double handed_ms = out.built ? probe.build_ms[s] : 0.0;
    out.own_ms = std::max(0.0, out.auto_ms - handed_ms);
    out.reason = probe_reason(d, measured, sample_rays, out.own_ms, out.built != nullptr, handed_ms);
    return out;
}

}  // namespace arbor::accel
