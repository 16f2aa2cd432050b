#include "instance_scenes.h"

#include <cmath>

namespace arbor::testing {

Transform make_transform(double angle, std::array<double, 3> axis, std::array<double, 3> scale, std::array<double, 3> move) {
    const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const double x = axis[0] / n, y = axis[1] / n, z = axis[2] / n, c = std::cos(angle), s = std::sin(angle), C = 1 - c;
    // Rodrigues' rotation matrix, times diag(scale).
    const double r[3][3] = {{c + x * x * C, x * y * C - z * s, x * z * C + y * s},
                            {y * x * C + z * s, c + y * y * C, y * z * C - x * s},
                            {z * x * C - y * s, z * y * C + x * s, c + z * z * C}};
    Transform t{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) t[std::size_t(4 * i + j)] = r[i][j] * scale[std::size_t(j)];
        t[std::size_t(4 * i + 3)] = move[std::size_t(i)];
    }
    return t;
}

Transform sheared(Transform t, double k) {
    // A * [[1, k, 0], [0, 1, 0], [0, 0, 1]]: column 1 gains k times column 0.
    for (int i = 0; i < 3; ++i) t[std::size_t(4 * i + 1)] += k * t[std::size_t(4 * i)];
    return t;
}

engine::Mesh flatten(const engine::Mesh& m, const Transform& t) {
    engine::Mesh out = m;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        const double p[3] = {m.x[i], m.y[i], m.z[i]};
        double w[3];
        for (int r = 0; r < 3; ++r)
            w[r] = t[std::size_t(4 * r)] * p[0] + t[std::size_t(4 * r + 1)] * p[1] + t[std::size_t(4 * r + 2)] * p[2] +
                   t[std::size_t(4 * r + 3)];
        out.x[i] = float(w[0]), out.y[i] = float(w[1]), out.z[i] = float(w[2]);
    }
    out.compute_bounds();
    return out;
}

std::uint32_t add(Scene& s, const engine::Mesh& m) {
    std::vector<float> xyz;
    xyz.reserve(3 * m.vertex_count());
    for (std::size_t i = 0; i < m.vertex_count(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
    return s.add_mesh(xyz, m.indices);
}

double edge_distance(const engine::Mesh& m, std::uint32_t prim, float u, float v) {
    const std::uint32_t* idx = &m.indices[3 * std::size_t(prim)];
    double p[3][3];
    for (int k = 0; k < 3; ++k) p[k][0] = m.x[idx[k]], p[k][1] = m.y[idx[k]], p[k][2] = m.z[idx[k]];
    const auto len = [&](int a, int b) {
        double s = 0;
        for (int c = 0; c < 3; ++c) s += (p[a][c] - p[b][c]) * (p[a][c] - p[b][c]);
        return std::sqrt(s);
    };
    double e1[3], e2[3];
    for (int c = 0; c < 3; ++c) e1[c] = p[1][c] - p[0][c], e2[c] = p[2][c] - p[0][c];
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double area2 = std::sqrt(cx * cx + cy * cy + cz * cz);
    // Height over the edge opposite corner k: area2 / |that edge|; the point's distance to it is
    // its barycentric weight of corner k times that height.
    const double w[3] = {1.0 - double(u) - double(v), double(u), double(v)};
    const double h[3] = {area2 / len(1, 2), area2 / len(0, 2), area2 / len(0, 1)};
    return std::min({std::fabs(w[0]) * h[0], std::fabs(w[1]) * h[1], std::fabs(w[2]) * h[2]});
}

std::vector<Transform> stiff_transforms() {
    std::vector<Transform> t;
    t.push_back(make_transform(0.0, {0, 0, 1}, {1, 1, 1}, {0, 0, 0}));
    t.push_back(make_transform(0.7, {1, 2, 3}, {1, 1, 1}, {4, 0.25, -0.5}));
    t.push_back(make_transform(2.1, {-1, 0.5, 0.2}, {-1, 1, 1}, {0, 4, 0.125}));              // mirror
    t.push_back(make_transform(1.3, {0.3, -1, 0.4}, {0.5, 1.25, 0.75}, {4, 4, 0.3}));        // non-uniform scale
    t.push_back(sheared(make_transform(0.4, {0, 0, 1}, {1, 1, 1}, {-4, 0, 1}), 0.35));        // shear
    t.push_back(make_transform(-0.9, {2, -1, 1}, {-0.6, -0.6, 0.6}, {-4, 4, -1}));           // mirror, uniform scale
    t.push_back(make_transform(3.0, {0, 1, 0}, {0.05, 0.05, 0.05}, {0, -4, 0}));              // small
    t.push_back(make_transform(0.2, {1, 1, 0}, {1.5, 0.2, 1}, {4, -4, 2}));                   // flattened
    return t;
}

}  // namespace arbor::testing
