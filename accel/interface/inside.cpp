#include "accel/interface/inside.h"

#include <array>
#include <cmath>
#include <vector>

namespace arbor::accel {

std::span<const Vec3f> inside_directions() {
    // Points of a golden-angle spiral on the sphere, turned off the axes by a fixed phase.
    static const std::array<Vec3f, 8> dirs = [] {
        std::array<Vec3f, 8> d{};
        for (int k = 0; k < 8; ++k) {
            const double z = 1.0 - (2.0 * k + 1.0) / 8.0 * 0.93;
            const double r = std::sqrt(1.0 - z * z), phi = 0.377 + 2.399963229728653 * k;
            d[std::size_t(k)] = {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
        }
        return d;
    }();
    return dirs;
}

namespace {

/// Counts each ray's crossings and says whether any of them is in the band.
class ParitySink final : public HitSink {
public:
    ParitySink(std::span<std::uint32_t> count, std::span<std::uint8_t> band, std::span<const float> band_t, float band_bary)
        : count_(count), band_(band), band_t_(band_t), band_bary_(band_bary) {}
    void take(std::size_t i, std::span<Hit> hits) override {
        count_[i] = std::uint32_t(hits.size());
        bool band = false;
        for (const Hit& h : hits)
            band = band || h.t <= band_t_[i] || h.u <= band_bary_ || h.v <= band_bary_ || 1.0f - h.u - h.v <= band_bary_;
        band_[i] = band;
    }

private:
    std::span<std::uint32_t> count_;
    std::span<std::uint8_t> band_;
    std::span<const float> band_t_;
    float band_bary_;
};

float coordinate_scale(const Bounds& b) {
    if (b.empty()) return 0.0f;
    float s = 0.0f;
    for (int k = 0; k < 3; ++k) s = std::max({s, std::fabs(b.lo[k]), std::fabs(b.hi[k]), b.hi[k] - b.lo[k]});
    return s;
}

}  // namespace

void inside_points(const Accel& accel, const Bounds& scene, std::span<const Vec3f> points, std::span<std::uint8_t> out,
                   const InsideConfig& cfg) {
    const std::span<const Vec3f> dirs = cfg.directions.empty() ? inside_directions() : cfg.directions;
    const int tries = std::max(1, std::min(cfg.max_directions, int(dirs.size())));
    const float scale = coordinate_scale(scene);
    // Points still undecided, with their votes so far (parities of the rays in the band).
    std::vector<std::uint32_t> todo, votes_in(points.size(), 0), votes_all(points.size(), 0);
    std::vector<float> band_t;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3f& p = points[i];
        out[i] = 0;
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) todo.push_back(std::uint32_t(i));
    }
    std::vector<Ray> rays;
    std::vector<std::uint32_t> count;
    std::vector<std::uint8_t> band;
    for (int k = 0; k < tries && !todo.empty(); ++k) {
        rays.resize(todo.size());
        band_t.resize(todo.size());
        count.assign(todo.size(), 0);
        band.assign(todo.size(), 0);
        for (std::size_t j = 0; j < todo.size(); ++j) {
            const Vec3f& p = points[todo[j]];
            rays[j] = {p, 0.0f, dirs[std::size_t(k)], std::numeric_limits<float>::infinity()};
            const float s = std::max({scale, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
            band_t[j] = cfg.band_t * s;  // unit directions: t is a distance
        }
        ParitySink sink(count, band, band_t, cfg.band_bary);
        accel.trace_all(rays, sink);
        std::size_t kept = 0;
        for (std::size_t j = 0; j < todo.size(); ++j) {
            const std::uint32_t i = todo[j];
            const bool odd = (count[j] & 1u) != 0;
            if (!band[j]) {
                out[i] = odd;
                continue;
            }
            votes_in[i] += odd;
            ++votes_all[i];
            if (k + 1 == tries) out[i] = 2 * votes_in[i] > votes_all[i];  // on the surface: the majority
            else todo[kept++] = i;
        }
        todo.resize(kept);
    }
}

}  // namespace arbor::accel
