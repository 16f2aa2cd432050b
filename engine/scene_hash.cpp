#include "engine/scene_hash.h"

#include <cstring>

namespace arbor::engine {

namespace {

std::uint64_t mix(std::uint64_t z) {  // splitmix64's finaliser (Steele, Lea, Flood 2014)
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

}  // namespace

Hasher& Hasher::bytes(std::span<const std::byte> data) {
    std::size_t i = 0;
    for (; i + 8 <= data.size(); i += 8) {
        std::uint64_t w;
        std::memcpy(&w, data.data() + i, 8);
        h_ = (h_ ^ w) * 0x9E3779B97F4A7C15ull;
        h_ ^= h_ >> 32;
    }
    std::uint64_t tail = 0;
    if (i < data.size()) std::memcpy(&tail, data.data() + i, data.size() - i);
    h_ = mix(h_ ^ tail ^ (std::uint64_t(data.size()) << 1));
    n_ += data.size();
    return *this;
}

Hasher& Hasher::text(std::string_view s) { return bytes(std::as_bytes(std::span<const char>(s.data(), s.size()))); }

Hasher& Hasher::number(double v) { return values(std::span<const double>(&v, 1)); }

std::uint64_t Hasher::value() const { return mix(h_ ^ n_); }

std::uint64_t scene_hash(const Scene& scene) {
    Hasher h;
    const Mesh& m = scene.mesh;
    h.values(std::span(m.x)).values(std::span(m.y)).values(std::span(m.z));
    h.values(std::span(m.indices)).values(std::span(m.material));
    auto vec = [&](const Vec3f& v) { h.number(v.x).number(v.y).number(v.z); };
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
