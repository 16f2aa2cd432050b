#include "engine/scene_hash.h"

#include "accel/util/splitmix64.h"

#include <cstring>

namespace arbor::engine {

Hasher& Hasher::bytes(std::span<const std::byte> data) {
    std::size_t i = 0;
    for (; i + 8 <= data.size(); i += 8) {
        std::uint64_t w;
        std::memcpy(&w, data.data() + i, 8);
        h_ = (h_ ^ w) * accel::splitmix64_gamma;
        h_ ^= h_ >> 32;
    }
    std::uint64_t tail = 0;
    if (i < data.size()) std::memcpy(&tail, data.data() + i, data.size() - i);
    h_ = accel::splitmix64_mix(h_ ^ tail ^ (std::uint64_t(data.size()) << 1));
    n_ += data.size();
    return *this;
}

Hasher& Hasher::text(std::string_view s) { return bytes(std::as_bytes(std::span<const char>(s.data(), s.size()))); }

Hasher& Hasher::number(double v) { return values(std::span<const double>(&v, 1)); }

std::uint64_t Hasher::value() const { return accel::splitmix64_mix(h_ ^ n_); }

std::uint64_t scene_hash(const Scene& scene) {
    Hasher h;
    const Mesh& m = scene.mesh;
    h.values(std::span(m.x)).values(std::span(m.y)).values(std::span(m.z));
    h.values(std::span(m.indices)).values(std::span(m.material));
    auto vec = [&](const Vec3f& v) { h.number(v.x).number(v.y).number(v.z); };
    h.number(double(scene.placed.drawn));
    for (const MeshPart& p : scene.placed.parts) h.number(double(p.first)).number(double(p.count));
    for (const PartInstance& i : scene.placed.instances) {
        h.number(double(i.part));
        h.values(std::span<const double>(i.transform.m));
    }
    for (const Material& mat : m.materials) {
        vec(mat.diffuse);
        vec(mat.mirror);
        vec(mat.emission);
    }
    const Camera& c = scene.camera;
    vec(c.eye);
    vec(c.look_at);
    vec(c.up);
    h.number(c.vfov_degrees);
    for (const PointLight& l : scene.lights) {
        vec(l.position);
        vec(l.intensity);
    }
    vec(scene.background);
    return h.value();
}

}  // namespace arbor::engine
