#include "engine/procedural.h"

#include "accel/util/splitmix64.h"

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace arbor::engine {

namespace {
}  // namespace

Mesh make_icosphere(Vec3f center, float radius, int subdivisions, float jitter, std::uint32_t seed) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3f> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
        {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (auto& p : v) p = simd::normalize(p);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(simd::normalize((v[a] + v[b]) * 0.5f));
            return mid[key] = std::uint32_t(v.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        next.reserve(f.size() * 4);
        for (const auto& tri : f) {
            const std::uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
            next.push_back({tri[0], a, c});
            next.push_back({tri[1], b, a});
            next.push_back({tri[2], c, b});
            next.push_back({a, b, c});
        }
        f = std::move(next);
    }
    Mesh m;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const float scale = jitter > 0 ? 1.0f + jitter * (2.0f * accel::unit_float24(accel::splitmix64(seed * 1000003ull + i)) - 1.0f) : 1.0f;
        m.add_vertex(center + v[i] * (radius * scale));
    }
    for (const auto& tri : f) m.add_triangle(tri[0], tri[1], tri[2]);
    m.compute_bounds();
    return m;
}

Mesh make_box(Vec3f lo, Vec3f hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i) m.add_vertex({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    // Outward-facing quads, each as two triangles.
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.add_triangle(q[0], q[1], q[2]);
        m.add_triangle(q[0], q[2], q[3]);
    }
    m.compute_bounds();
    return m;
}

Mesh make_ground(float height, float cx, float cz, float half_size) {
    Mesh m;
    m.add_vertex({cx - half_size, height, cz - half_size});
    m.add_vertex({cx - half_size, height, cz + half_size});
    m.add_vertex({cx + half_size, height, cz + half_size});
    m.add_vertex({cx + half_size, height, cz - half_size});
    m.add_triangle(0, 1, 2);
    m.add_triangle(0, 2, 3);
    m.compute_bounds();
    return m;
}

Mesh make_torus(Vec3f center, float major_radius, float minor_radius, int rings, int sides) {
    Mesh m;
    const float two_pi = 2.0f * std::numbers::pi_v<float>;
    for (int i = 0; i < rings; ++i) {
        const float a = two_pi * float(i) / float(rings);
        for (int j = 0; j < sides; ++j) {
            const float b = two_pi * float(j) / float(sides);
            const float r = major_radius + minor_radius * std::cos(b);
            m.add_vertex(center + Vec3f{r * std::cos(a), minor_radius * std::sin(b), r * std::sin(a)});
        }
    }
    auto id = [&](int i, int j) { return std::uint32_t(((i % rings) * sides) + (j % sides)); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < sides; ++j) {
            m.add_triangle(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            m.add_triangle(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        }
    m.compute_bounds();
    return m;
}

Mesh with_material(Mesh mesh, const Material& mat) {
    mesh.materials = {mat};
    mesh.material.assign(mesh.triangle_count(), 0);
    return mesh;
}

}  // namespace arbor::engine
