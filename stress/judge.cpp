#include "stress/judge.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace arbor::stress {

namespace {

constexpr double rel_slack = 1e-4;  // the t tolerance of spec/rayfile.md, relative only
constexpr std::size_t max_examples = 4;

enum class Outcome { ok, false_miss, false_hit, double_hit };

struct Verdict {
    Outcome outcome = Outcome::ok;
    double dt = -1.0;  ///< for accepted hits
    const char* why = "";
};

Verdict judge_one(const Ray& ray, const RayTag& tag, const OracleAnswer& a, const Oracle& oracle, const Hit& h,
                  bool closest) {
    if (!a.traceable) return h.is_hit() ? Verdict{Outcome::false_hit, -1.0, "untraceable ray hit"} : Verdict{};
    if (!h.is_hit()) {
        if (a.certain_hit()) return {Outcome::false_miss, -1.0, "missed a certain hit"};
        if (tag.must_hit()) return {Outcome::false_miss, -1.0, "missed a closed surface"};
        return {};
    }
    if (h.prim == tag.source_prim) return {Outcome::double_hit, -1.0, "hit the triangle it leaves"};
    const TriVerdict v = oracle.classify(ray, h.prim);
    const bool real = v.kind != TriVerdict::miss && std::fabs(double(h.t) - v.t) <= v.tol + rel_slack * std::fabs(v.t);
    if (!real) {
        if (tag.continuation) return {Outcome::double_hit, -1.0, "hit again past the crossing"};
        return {Outcome::false_hit, -1.0, v.kind == TriVerdict::miss ? "triangle not hit" : "wrong t"};
    }
    if (closest) {
        double limit = std::numeric_limits<double>::infinity();
        if (a.certain_hit()) limit = a.t_hit + a.t_hit_tol + rel_slack * std::fabs(a.t_hit);
        if (tag.must_hit() && std::isfinite(tag.surface_t))
            limit = std::min(limit, double(tag.surface_t) + rel_slack * std::fabs(double(tag.surface_t)));
        if (v.t - v.tol > limit) return {Outcome::false_miss, -1.0, "hit behind the first surface"};
    }
    const double err = std::fabs(double(h.t) - v.t);
    return {Outcome::ok, v.t != 0.0 ? err / std::fabs(v.t) : err, ""};
}

std::string describe(const StressCase& c, std::size_t i, const OracleAnswer& a, const Hit& h, bool closest,
                     const char* why) {
    const Ray& r = c.rays[i];
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s ray %zu (%s): %s; o=(%.9g %.9g %.9g) d=(%.9g %.9g %.9g) t=[%.9g, %.9g]; got t=%.9g prim=%u; "
                  "oracle t=%.17g prim=%u band=%d",
                  c.name.c_str(), i, closest ? "closest" : "any", why, r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y,
                  r.dir.z, r.tnear, r.tfar, h.t, h.prim, a.t_hit, a.prim, int(a.band));
    return buf;
}

}  // namespace

Tally judge(const StressCase& c, const Oracle& oracle, std::span<const OracleAnswer> answers,
            std::span<const Hit> closest, std::span<const Hit> any) {
    Tally out;
    out.rays = c.rays.size();
    for (std::size_t i = 0; i < c.rays.size(); ++i) {
        const RayTag tag = i < c.tags.size() ? c.tags[i] : RayTag{};
        out.band += answers[i].band;
        out.hits += closest[i].is_hit();
        for (int q = 0; q < (any.empty() ? 1 : 2); ++q) {
            const bool is_closest = q == 0;
            const Hit& h = is_closest ? closest[i] : any[i];
            const Verdict v = judge_one(c.rays[i], tag, answers[i], oracle, h, is_closest);
            switch (v.outcome) {
            case Outcome::ok:
                if (v.dt >= 0.0 && !answers[i].band) out.max_dt = std::max(out.max_dt, v.dt);
                continue;
            case Outcome::false_miss: ++out.false_miss; break;
            case Outcome::false_hit: ++out.false_hit; break;
            case Outcome::double_hit: ++out.double_hit; break;
            }
            if (out.examples.size() < max_examples) out.examples.push_back(describe(c, i, answers[i], h, is_closest, v.why));
        }
    }
    return out;
}

bool has_parity(const StressCase& c) {
    return std::any_of(c.tags.begin(), c.tags.end(), [](const RayTag& t) { return t.parity >= 0; });
}

void judge_crossings(const StressCase& c, std::span<const std::vector<Hit>> lists, Tally& out) {
    for (std::size_t i = 0; i < c.rays.size() && i < c.tags.size(); ++i) {
        const int parity = c.tags[i].parity;
        if (parity < 0 || !accel::ray_is_traceable(c.rays[i])) continue;
        std::vector<Hit> l;
        for (const Hit& h : lists[i])
            if (h.prim < c.parity_prims) l.push_back(h);
        if (int(l.size() % 2) == parity) continue;
        // Two crossings at one point: the lists are sorted by t, so they are neighbours.
        bool twice = false;
        for (std::size_t k = 1; k < l.size(); ++k)
            twice = twice || std::fabs(double(l[k].t) - double(l[k - 1].t)) <= 1e-5 * std::fabs(double(l[k].t));
        twice ? ++out.double_hit : ++out.false_miss;
        if (out.examples.size() < max_examples) {
            const Ray& r = c.rays[i];
            char buf[512];
            std::snprintf(buf, sizeof buf,
                          "%s ray %zu (all hits): %zu crossings, expected an %s count%s; o=(%.9g %.9g %.9g) "
                          "d=(%.9g %.9g %.9g) t=[%.9g, %.9g]",
                          c.name.c_str(), i, l.size(), parity ? "odd" : "even", twice ? " (two at one t)" : "", r.org.x,
                          r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar);
            out.examples.push_back(buf);
        }
    }
}

}  // namespace arbor::stress
