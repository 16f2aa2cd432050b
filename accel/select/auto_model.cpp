#include "accel/select/auto_model.h"

#include "accel/interface/accel.h"

#include <algorithm>
#include <cmath>
#include <charconv>
#include <system_error>
#include <stdexcept>

namespace arbor::accel {

/// perf/model/auto_model.txt, embedded by CMake (auto_model_text.cpp in the build tree).
extern const char* const auto_model_text;

namespace {

double safe_log(double v) { return std::log(std::max(v, 1e-6)); }

[[noreturn]] void bad_line(std::size_t line, const std::string& what) {
    throw std::invalid_argument("auto model, line " + std::to_string(line) + ": " + what);
}

}  // namespace

std::optional<double> feature_value(std::string_view name, const SceneShape& scene, const RayShape& rays, double threads) {
    if (name == "one") return 1.0;
    if (name == "log2_triangles") return std::log2(std::max<double>(double(scene.triangles), 1.0));
    if (name == "log_overlap") return safe_log(scene.overlap);
    if (name == "log_spread") return safe_log(scene.spread);
    if (name == "log_size_tail") return safe_log(scene.size_tail);
    if (name == "log_thinness") return safe_log(scene.thinness);
    if (name == "coherent") return rays.coherent;
    if (name == "together") return rays.together;
    if (name == "any_hit") return rays.query == Query::any ? 1.0 : 0.0;
    if (name == "log2_threads") return std::log2(std::max(threads, 1.0));
    return std::nullopt;
}

namespace {
/// The whitespace-separated words of one line of a model. (Not an istringstream: a fresh process
/// would pay for the stream and locale set-up on its first parse, a large part of auto's own work
/// on a small job.)
class Words {
public:
    explicit Words(std::string_view line) : s_(line) {}
    /// The next word; false at the end of the line.
    bool next(std::string_view& word) {
        skip();
        if (s_.empty()) return false;
        std::size_t n = 0;
        while (n < s_.size() && !space(s_[n])) ++n;
        word = s_.substr(0, n);
        s_.remove_prefix(n);
        return true;
    }
    /// The next word as a number; false at the end of the line or when the word is not one.
    template <class V> bool number(V& v) {
        std::string_view w;
        if (!next(w)) return false;
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
        return ec == std::errc() && end == w.data() + w.size();
    }
    /// The rest of the line, its leading spaces skipped.
    std::string_view rest() {
        skip();
        return s_;
    }

private:
    static bool space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
    void skip() {
        while (!s_.empty() && space(s_.front())) s_.remove_prefix(1);
    }
    std::string_view s_;
};
}  // namespace

AutoModel AutoModel::parse(std::string_view text) {
    AutoModel m;
    std::size_t number = 0;
    bool header = false;
    const SceneShape probe_scene;
    const RayShape probe_rays;
    auto read_features = [&](Words& ls, std::vector<std::string>& out) {
        for (std::string_view f; ls.next(f);) {
            if (!feature_value(f, probe_scene, probe_rays, 1.0)) bad_line(number, "unknown feature '" + std::string(f) + "'");
            out.emplace_back(f);
        }
        if (out.empty()) bad_line(number, "no features");
    };
    auto read_coefs = [&](Words& ls, std::size_t count) {
        Linear l;
        while (!ls.rest().empty()) {
            double v = 0.0;
            if (!ls.number(v)) bad_line(number, "a coefficient is not a number");
            l.coef.push_back(v);
        }
        if (l.coef.size() != count)
            bad_line(number, std::to_string(l.coef.size()) + " coefficients for " + std::to_string(count) + " features");
        for (double v : l.coef)
            if (!std::isfinite(v)) bad_line(number, "a coefficient is not finite");
        return l;
    };
    auto read_kind = [&](Words& ls) {
        std::string_view name;
        ls.next(name);
        const auto k = parse_accel_kind(name);
        if (!k || *k == AccelKind::automatic) bad_line(number, "unknown structure '" + std::string(name) + "'");
        return *k;
    };
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++number;
        if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        Words ls(line);
        std::string_view key;
        if (!ls.next(key)) continue;
        if (!header) {
            int version = 0;
            if (key != "arbor-auto-model" || !ls.number(version) || version != 1) bad_line(number, "expected 'arbor-auto-model 1'");
            header = true;
        } else if (key == "source") {
            m.source_ = std::string(ls.rest());
        } else if (key == "trace_features") {
            read_features(ls, m.trace_features_);
        } else if (key == "build_features") {
            read_features(ls, m.build_features_);
        } else if (key == "margin") {
            if (!ls.number(m.margin_) || !(m.margin_ >= 0.0)) bad_line(number, "margin must be a number >= 0");
        } else if (key == "prefer") {
            m.preferred_ = read_kind(ls);
            if (!ls.number(m.prefer_share_) || !(m.prefer_share_ >= 0.0 && m.prefer_share_ < 1.0))
                bad_line(number, "expected 'prefer STRUCTURE SHARE' with 0 <= SHARE < 1");
        } else if (key == "clamp") {
            Clamp c;
            std::string_view feature;
            if (!ls.next(feature) || !ls.number(c.lo) || !ls.number(c.hi) || !(c.lo <= c.hi))
                bad_line(number, "expected 'clamp FEATURE LO HI'");
            c.feature = std::string(feature);
            if (!feature_value(c.feature, probe_scene, probe_rays, 1.0)) bad_line(number, "unknown feature '" + c.feature + "'");
            m.clamps_.push_back(c);
        } else if (key == "trace") {
            const AccelKind k = read_kind(ls);
            std::string_view path;
            ls.next(path);
            const auto p = parse_trace_path(path);
            if (!p || *p == TracePath::best) bad_line(number, "unknown path '" + std::string(path) + "'");
            if (m.trace_features_.empty()) bad_line(number, "trace before trace_features");
            m.trace_.push_back({k, *p, read_coefs(ls, m.trace_features_.size())});
        } else if (key == "build") {
            const AccelKind k = read_kind(ls);
            if (m.build_features_.empty()) bad_line(number, "build before build_features");
            m.build_.push_back({k, read_coefs(ls, m.build_features_.size())});
        } else {
            bad_line(number, "unknown keyword '" + std::string(key) + "'");
        }
    }
    if (!header) throw std::invalid_argument("auto model: empty");
    if (m.structures().empty()) throw std::invalid_argument("auto model: no structure has both a build and a trace line");
    return m;
}

double AutoModel::eval(const Linear& l, const std::vector<std::string>& features, const SceneShape& scene,
                       const RayShape& rays, double threads) const {
    double s = 0.0;
    for (std::size_t i = 0; i < features.size(); ++i) {
        double v = *feature_value(features[i], scene, rays, threads);
        for (const Clamp& c : clamps_)
            if (c.feature == features[i]) v = std::clamp(v, c.lo, c.hi);
        s += l.coef[i] * v;
    }
    return std::exp(s);
}

bool AutoModel::has(AccelKind kind, TracePath path) const {
    const bool built = std::any_of(build_.begin(), build_.end(), [&](const Build& b) { return b.kind == kind; });
    return built && std::any_of(trace_.begin(), trace_.end(), [&](const Trace& t) { return t.kind == kind && t.path == path; });
}

double AutoModel::ns_per_ray(AccelKind kind, TracePath path, const SceneShape& scene, const RayShape& rays,
                             double threads) const {
    for (const Trace& t : trace_)
        if (t.kind == kind && t.path == path) return eval(t.fit, trace_features_, scene, rays, threads);
    throw std::invalid_argument("auto model: no trace time for " + std::string(to_string(kind)) + "/" +
                                std::string(to_string(path)));
}

double AutoModel::build_ms(AccelKind kind, const SceneShape& scene, double threads) const {
    for (const Build& b : build_)
        if (b.kind == kind) return eval(b.fit, build_features_, scene, RayShape{}, threads);
    throw std::invalid_argument("auto model: no build time for " + std::string(to_string(kind)));
}

std::vector<AccelKind> AutoModel::structures() const {
    std::vector<AccelKind> out;
    for (const Build& b : build_)
        if (std::any_of(trace_.begin(), trace_.end(), [&](const Trace& t) { return t.kind == b.kind; }) &&
            std::find(out.begin(), out.end(), b.kind) == out.end())
            out.push_back(b.kind);
    return out;
}

const AutoModel& builtin_auto_model() {
    static const AutoModel model = AutoModel::parse(auto_model_text);
    return model;
}

}  // namespace arbor::accel
