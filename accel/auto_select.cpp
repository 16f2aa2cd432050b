#include "accel/auto_select.h"

#include "accel/timer.h"
#include "accel/trace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
    };

    TriangleView tris;
    AutoConfig cfg;
    std::size_t n = 0, m = 0;  // triangles of the scene and of the subset (0: calibrated whole)
    std::vector<std::uint32_t> subset_indices;
    Bounds bounds;
    std::vector<Candidate> cands;
    Candidate* anchor = nullptr;
    double spent_ms = 0.0;
    std::size_t last_sample = 0;  // rays of the last predict()

    /// Trace time per ray, ns, of each structure: the fastest of cfg.repeats traces of `rays`, the
    /// repeats of all structures interleaved so that a burst of other work does not hit one alone.
    std::vector<double> ns_per_ray(const std::vector<const Accel*>& accels, std::span<const Ray> rays,
                                   bool any_hit) const {
        std::vector<double> best(accels.size(), std::numeric_limits<double>::infinity());
        if (rays.empty()) return std::vector<double>(accels.size(), 0.0);
        std::vector<Hit> hits(rays.size());
        for (int r = 0; r < std::max(cfg.repeats, 1); ++r)
            for (std::size_t i = 0; i < accels.size(); ++i) {
                const Timer t;
                trace_parallel(*accels[i], rays, hits, any_hit ? Query::any : Query::closest);
                best[i] = std::min(best[i], t.ms());
            }
        for (double& b : best) b *= 1e6 / double(rays.size());
        return best;
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

    TriangleView subset;
    if (s.n > cfg.full_triangles && cfg.full_triangles > 0) {
        // Stratified random subset: one triangle from each of m equal runs of the numbering.
        s.m = cfg.full_triangles;
        s.subset_indices.reserve(3 * s.m);
        for (std::size_t j = 0; j < s.m; ++j) {
            const double pos = (double(j) + double(u01(cfg.seed ^ 0xABCDull, j))) * double(s.n) / double(s.m);
            const std::size_t t = std::min(s.n - 1, std::size_t(pos));
            for (int k = 0; k < 3; ++k) s.subset_indices.push_back(tris.indices[3 * t + std::size_t(k)]);
        }
        subset = {tris.x, tris.y, tris.z, s.subset_indices};
    }

    for (const AccelKind k : candidates) {
        if (k == AccelKind::brute && s.n > cfg.brute_triangles) continue;
        Impl::Candidate c{k, nullptr, nullptr};
        try {
            const Timer bt;
            if (s.m) c.sub = make_accel(k, subset, cfg.build), c.sub_ms = bt.ms();
            else c.whole = make_accel(k, tris, cfg.build), c.whole_ms = bt.ms();
        } catch (const std::invalid_argument&) {
            continue;  // not in this build
        }
        s.cands.push_back(std::move(c));
    }
    if (s.cands.empty()) throw std::invalid_argument("auto: no acceleration structure can be built");
    if (s.m) {
        // The anchor: lbvh when there is one (the cheapest build), else the fastest subset build.
        s.anchor = &s.cands.front();
        for (auto& c : s.cands)
            if (c.kind == AccelKind::lbvh || (s.anchor->kind != AccelKind::lbvh && c.sub_ms < s.anchor->sub_ms)) s.anchor = &c;
        const Timer bt;
        s.anchor->whole = make_accel(s.anchor->kind, tris, cfg.build);
        s.anchor->whole_ms = bt.ms();
    }
    s.spent_ms = timer.ms();
}

AutoSelector::~AutoSelector() = default;

double AutoSelector::calibration_ms() const { return impl_->spent_ms; }

std::unique_ptr<Accel> AutoSelector::take_built(AccelKind kind) {
    for (auto& c : impl_->cands)
        if (c.kind == kind) return std::move(c.whole);
    return nullptr;
}

AutoChoice AutoSelector::choose(std::span<const Ray> sample, bool any_hit, double budget) {
    return pick(predict(sample, any_hit), budget);
}

std::vector<AutoPrediction> AutoSelector::predict(std::span<const Ray> sample, bool any_hit) {
    const Timer timer;
    Impl& s = *impl_;
    std::vector<Ray> rays;
    if (sample.empty()) {
        rays = rays_into_bounds(s.bounds, s.cfg.sample_rays, s.cfg.seed);
    } else if (sample.size() <= s.cfg.sample_rays) {
        rays.assign(sample.begin(), sample.end());
    } else {
        // Runs of consecutive rays spread over the sample: rays from one image tile stay together,
        // so coherent rays are timed as coherent (a strided pick would make them incoherent).
        const std::size_t run = std::clamp<std::size_t>(s.cfg.sample_rays, 1, 256);  // < sample.size()
        const std::size_t runs = (s.cfg.sample_rays + run - 1) / run;
        for (std::size_t r = 0; r < runs; ++r) {
            const std::size_t first = r * (sample.size() - run) / std::max<std::size_t>(runs - 1, 1);
            rays.insert(rays.end(), sample.begin() + std::ptrdiff_t(first), sample.begin() + std::ptrdiff_t(first + run));
        }
    }
    s.last_sample = rays.size();

    std::vector<AutoPrediction> out;
    if (!s.m) {
        // Taken structures (take_built) can no longer be timed: they keep infinite trace time.
        std::vector<const Accel*> timed;
        for (auto& c : s.cands)
            if (c.whole) timed.push_back(c.whole.get());
        const std::vector<double> ns = s.ns_per_ray(timed, rays, any_hit);
        std::size_t k = 0;
        for (auto& c : s.cands) {
            const double t = c.whole ? ns[k++] : std::numeric_limits<double>::infinity();
            out.push_back({c.kind, c.whole_ms, t, 0.0, c.whole != nullptr});
        }
    } else {
        std::vector<const Accel*> timed;
        for (auto& c : s.cands) timed.push_back(c.sub.get());
        if (s.anchor->whole) timed.push_back(s.anchor->whole.get());
        const std::vector<double> ns = s.ns_per_ray(timed, rays, any_hit);
        const auto anchor_index = std::size_t(s.anchor - s.cands.data());
        const double anchor_sub = ns[anchor_index];
        const double anchor_whole = s.anchor->whole ? ns.back() : anchor_sub;
        // Build time: subset time x N/m (x log N / log m for top-down builders), corrected by how
        // the anchor's own build scaled from the subset to the whole scene (caches, threads).
        const double ratio = double(s.n) / double(s.m);
        const double correction = s.anchor->sub_ms > 0 ? s.anchor->whole_ms / (s.anchor->sub_ms * ratio) : 1.0;
        const double log_ratio = std::log2(double(s.n)) / std::log2(double(s.m));
        for (std::size_t i = 0; i < s.cands.size(); ++i) {
            const auto& c = s.cands[i];
            AutoPrediction p{c.kind, 0.0, 0.0, 0.0, c.whole != nullptr};
            if (&c == s.anchor) {
                p.build_ms = c.whole_ms;
                p.ns_per_ray = anchor_whole;
            } else {
                p.build_ms = c.sub_ms * ratio * correction * (c.kind == AccelKind::lbvh ? 1.0 : log_ratio);
                p.ns_per_ray = anchor_sub > 0 ? anchor_whole * ns[i] / anchor_sub : anchor_whole;
            }
            out.push_back(p);
        }
    }
    s.spent_ms += timer.ms();
    return out;
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
    const AutoPrediction& best = out.predictions.front();
    out.kind = best.kind;
    out.calibration_ms = s.spent_ms;

    std::string r = std::string(to_string(best.kind)) + ": predicted " + human_ms(best.total_ms) + " for " +
                    human_count(budget) + " rays (build " + human_ms(best.build_ms) + " + " +
                    human_count(best.ns_per_ray > 0 ? 1e3 / best.ns_per_ray * 1e6 : 0.0) + " rays/s)";
    if (out.predictions.size() > 1) {
        const AutoPrediction& next = out.predictions[1];
        r += "; next " + std::string(to_string(next.kind)) + " " + human_ms(next.total_ms);
    }
    r += s.m ? "; calibrated on " + human_count(double(s.m)) + " of " + human_count(double(s.n)) + " triangles + whole " +
                   std::string(to_string(s.anchor->kind))
             : "; calibrated on all " + human_count(double(s.n)) + " triangles";
    r += ", " + std::to_string(s.last_sample) + " rays, " + human_ms(s.spent_ms);
    out.reason = r;
    return out;
}

}  // namespace arbor::accel
