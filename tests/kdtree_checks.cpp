#include "kdtree_checks.h"

#include "accel/kdtree/kdtree_clip.h"
#include "engine/procedural.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace arbor::testing {

using accel::Bounds;
using accel::KdLeaf;
using accel::KdNode;
using accel::KdTree;

std::vector<Bounds> kd_node_boxes(const KdTree& tree) {
    std::vector<Bounds> boxes(tree.nodes.size());
    boxes[0] = tree.box;
    // Children come after their parent, so one forward pass fills every box.
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
        const KdNode n = tree.nodes[i];
        if (n.is_leaf()) continue;
        Bounds l = boxes[i], r = boxes[i];
        l.hi[n.axis()] = n.split;
        r.lo[n.axis()] = n.split;
        boxes[i + 1] = l;
        boxes[n.index()] = r;
    }
    return boxes;
}

std::vector<std::uint32_t> kd_subtree_ends(const KdTree& tree) {
    std::vector<std::uint32_t> end(tree.nodes.size());
    for (std::size_t i = tree.nodes.size(); i-- > 0;) {
        const KdNode n = tree.nodes[i];
        end[i] = n.is_leaf() ? std::uint32_t(i + 1) : end[n.index()];
    }
    return end;
}

std::uint32_t kd_locate(const KdTree& tree, const Vec3f& p) {
    std::uint32_t node = 0;
    while (!tree.nodes[node].is_leaf()) {
        const KdNode n = tree.nodes[node];
        node = p[n.axis()] >= n.split ? n.index() : node + 1;
    }
    return node;
}

namespace {

struct D3 {
    double x, y, z;
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }
D3 d3(const Vec3f& v) { return {v.x, v.y, v.z}; }

/// Largest separation (>0: a gap, <0: penetration) between the triangle and the closed box over
/// the 13 separating axes, in distance units (axes of zero length are skipped).
double separation(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Bounds& box) {
    const D3 lo = d3(box.lo), hi = d3(box.hi);
    const D3 ctr{(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
    const D3 h{(hi.x - lo.x) / 2, (hi.y - lo.y) / 2, (hi.z - lo.z) / 2};
    const D3 v[3] = {sub(d3(a), ctr), sub(d3(b), ctr), sub(d3(c), ctr)};
    double sep = -INFINITY;
    const auto test = [&](D3 axis) {
        const double len = norm(axis);
        if (!(len > 0.0)) return;
        const double r = h.x * std::fabs(axis.x) + h.y * std::fabs(axis.y) + h.z * std::fabs(axis.z);
        const double p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
        const double pmin = std::min({p0, p1, p2}), pmax = std::max({p0, p1, p2});
        sep = std::max(sep, std::max(pmin - r, -r - pmax) / len);
    };
    const D3 units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const D3& u : units) test(u);
    const D3 e[3] = {sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
    test(cross(e[0], e[1]));
    for (const D3& ei : e)
        for (const D3& u : units) test(cross(ei, u));
    return sep;
}

double scale_of(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Bounds& box) {
    double s = 0.0;
    for (const Vec3f& p : {a, b, c, box.lo, box.hi})
        for (int k = 0; k < 3; ++k) s = std::max(s, double(std::fabs(p[k])));
    return std::max(s, 1e-30);
}

bool leaf_has_prim(const KdTree& tree, const KdLeaf& leaf, std::uint32_t prim) {
    for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
        if (tree.tris[tree.refs[i]].prim == prim) return true;
    return false;
}

bool closed_contains(const Bounds& b, const Vec3f& p) {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
}

}  // namespace

bool triangle_meets_open_box(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Bounds& box) {
    return separation(a, b, c, box) < -1e-6 * scale_of(a, b, c, box);
}

std::string check_kdtree_structure(const KdTree& tree, const accel::TriangleView& tris) {
    std::ostringstream err;
    if (tree.nodes.empty()) return "no nodes";
    const auto boxes = kd_node_boxes(tree);
    std::vector<int> node_seen(tree.nodes.size(), 0), leaf_seen(tree.leaves.size(), 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{0, 0}};
    while (!stack.empty()) {
        const auto [i, depth] = stack.back();
        stack.pop_back();
        if (node_seen[i]++) return (err << "node " << i << " reached twice", err.str());
        const KdNode n = tree.nodes[i];
        if (n.is_leaf()) {
            if (n.index() >= tree.leaves.size()) return (err << "leaf index out of range at node " << i, err.str());
            if (leaf_seen[n.index()]++) return (err << "leaf " << n.index() << " referenced twice", err.str());
            if (depth > tree.depth_limit) return (err << "leaf at depth " << depth << " > limit", err.str());
            const KdLeaf& l = tree.leaves[n.index()];
            for (int k = 0; k < 3; ++k)
                if (l.box.lo[k] != boxes[i].lo[k] || l.box.hi[k] != boxes[i].hi[k])
                    return (err << "leaf " << n.index() << " box differs from its splits", err.str());
            if (std::size_t(l.first) + l.count > tree.refs.size()) return "leaf refs out of range";
            for (std::uint32_t r = l.first; r < l.first + l.count; ++r) {
                if (tree.refs[r] >= tree.tris.size()) return "ref out of range";
                if (r > l.first && tree.tris[tree.refs[r - 1]].prim >= tree.tris[tree.refs[r]].prim)
                    return (err << "leaf " << n.index() << " refs not ascending", err.str());
            }
            continue;
        }
        const int k = n.axis();
        if (!(boxes[i].lo[k] < n.split && n.split < boxes[i].hi[k]))
            return (err << "node " << i << " split " << n.split << " not inside its box", err.str());
        if (n.index() <= i + 1 || n.index() >= tree.nodes.size())
            return (err << "node " << i << " right child " << n.index() << " out of order", err.str());
        stack.push_back({n.index(), depth + 1});
        stack.push_back({i + 1, depth + 1});
    }
    if (std::count(node_seen.begin(), node_seen.end(), 0)) return "unreachable nodes";
    if (std::count(leaf_seen.begin(), leaf_seen.end(), 0)) return "unreferenced leaf records";
    std::vector<int> stored(tris.triangle_count(), 0);
    for (const auto& t : tree.tris) {
        if (t.prim >= stored.size() || stored[t.prim]++) return "triangle stored twice or out of range";
        for (int k = 0; k < 3; ++k) {
            const Vec3f v = tris.corner(t.prim, k), s = k == 0 ? t.v0 : (k == 1 ? t.v1 : t.v2);
            if (v.x != s.x || v.y != s.y || v.z != s.z) return "stored corners differ from the input";
        }
    }
    for (std::size_t i = 0; i < stored.size(); ++i)
        if (bool(stored[i]) != tris.triangle_is_finite(i))
            return (err << "triangle " << i << (stored[i] ? " non-finite but stored" : " finite but not stored"), err.str());
    return {};
}

std::string check_kdtree_refs(const KdTree& tree, const accel::TriangleView& tris) {
    std::ostringstream err;
    for (std::size_t li = 0; li < tree.leaves.size(); ++li) {
        const KdLeaf& leaf = tree.leaves[li];
        std::vector<char> in(tris.triangle_count(), 0);
        for (std::uint32_t r = leaf.first; r < leaf.first + leaf.count; ++r) in[tree.tris[tree.refs[r]].prim] = 1;
        for (std::size_t t = 0; t < tris.triangle_count(); ++t) {
            if (!tris.triangle_is_finite(t)) continue;
            const Vec3f a = tris.corner(t, 0), b = tris.corner(t, 1), c = tris.corner(t, 2);
            if (!in[t] && triangle_meets_open_box(a, b, c, leaf.box))
                return (err << "triangle " << t << " meets leaf " << li << " but is not referenced", err.str());
            accel::Bounds tb;
            for (const Vec3f& p : {a, b, c}) tb.grow(p);
            if (in[t] && accel::intersect(tb, leaf.box).empty())
                return (err << "triangle " << t << " referenced by leaf " << li << " its bounds miss", err.str());
        }
    }
    // Every corner of every triangle lies in some leaf that references the triangle.
    for (std::size_t t = 0; t < tris.triangle_count(); ++t) {
        if (!tris.triangle_is_finite(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = tris.corner(t, k);
            bool found = false;
            std::vector<std::uint32_t> stack{0};
            while (!stack.empty() && !found) {
                const std::uint32_t i = stack.back();
                stack.pop_back();
                const KdNode n = tree.nodes[i];
                if (n.is_leaf()) {
                    const KdLeaf& leaf = tree.leaves[n.index()];
                    found = closed_contains(leaf.box, p) && leaf_has_prim(tree, leaf, std::uint32_t(t));
                    continue;
                }
                if (p[n.axis()] <= n.split) stack.push_back(i + 1);
                if (p[n.axis()] >= n.split) stack.push_back(n.index());
            }
            if (!found) return (err << "corner " << k << " of triangle " << t << " is in no leaf that has it", err.str());
        }
    }
    return {};
}

std::string check_kdtree_ropes(const KdTree& tree) {
    std::ostringstream err;
    const auto boxes = kd_node_boxes(tree);
    const auto ends = kd_subtree_ends(tree);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.05f, 0.95f);
    for (std::size_t li = 0; li < tree.leaves.size(); ++li) {
        const KdLeaf& leaf = tree.leaves[li];
        for (int f = 0; f < 6; ++f) {
            const int k = f / 2;
            const bool max_face = f & 1;
            const float q = max_face ? leaf.box.hi[k] : leaf.box.lo[k];
            const bool on_scene = q == (max_face ? tree.box.hi[k] : tree.box.lo[k]);
            const std::uint32_t rope = leaf.rope[f];
            if (on_scene) {
                if (rope != accel::kd_no_rope) return (err << "leaf " << li << " face " << f << " on the scene box has a rope", err.str());
                continue;
            }
            if (rope >= tree.nodes.size()) return (err << "leaf " << li << " face " << f << " rope missing", err.str());
            const Bounds& r = boxes[rope];
            if ((max_face ? r.lo[k] : r.hi[k]) != q)
                return (err << "leaf " << li << " face " << f << ": rope node does not start at the face", err.str());
            for (int j = 0; j < 3; ++j)
                if (j != k && (r.lo[j] > leaf.box.lo[j] || r.hi[j] < leaf.box.hi[j]))
                    return (err << "leaf " << li << " face " << f << ": rope node does not hold the face", err.str());
            const KdNode n = tree.nodes[rope];
            if (!n.is_leaf() && (n.axis() == k || !(leaf.box.lo[n.axis()] < n.split && n.split < leaf.box.hi[n.axis()])))
                return (err << "leaf " << li << " face " << f << ": rope node is not the smallest", err.str());
            // Points just beyond the face must be located inside the rope's subtree.
            const float beyond = r.lo[k] * 0.5f + r.hi[k] * 0.5f;  // inside the rope node, past the face
            if (!(beyond > r.lo[k] && beyond < r.hi[k])) continue;  // a one-ulp neighbour: no room
            for (int s = 0; s < 5; ++s) {
                Vec3f p;
                bool inside = true;
                for (int j = 0; j < 3; ++j) {
                    const float t = s == 0 ? 0.5f : u(rng);
                    p[j] = j == k ? beyond : leaf.box.lo[j] * (1.0f - t) + leaf.box.hi[j] * t;
                    inside &= j == k || (p[j] > leaf.box.lo[j] && p[j] < leaf.box.hi[j]);
                }
                if (!inside) continue;  // a face a few ulps wide: no point strictly inside it
                const std::uint32_t at = kd_locate(tree, p);
                if (at < rope || at >= ends[rope])
                    return (err << "leaf " << li << " face " << f << ": point (" << p.x << " " << p.y << " " << p.z
                                << ") beyond the face is in node " << at << ", outside the rope's subtree [" << rope
                                << ", " << ends[rope] << ")", err.str());
            }
        }
    }
    return {};
}

engine::Mesh random_soup(std::size_t n, float size, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-size, size);
    engine::Mesh m;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f c{pos(rng), pos(rng), pos(rng)};
        const std::uint32_t a = m.add_vertex(c + Vec3f{off(rng), off(rng), off(rng)});
        const std::uint32_t b = m.add_vertex(c + Vec3f{off(rng), off(rng), off(rng)});
        const std::uint32_t d = m.add_vertex(c + Vec3f{off(rng), off(rng), off(rng)});
        m.add_triangle(a, b, d);
    }
    m.compute_bounds();
    return m;
}

engine::Mesh integer_grid(int n) {
    engine::Mesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.add_vertex({float(i), float(j), 0.0f});
    const auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    m.compute_bounds();
    return m;
}

engine::Mesh integer_cubes(int n) {
    engine::Mesh m;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                if ((x + y + z) % 2) continue;
                const engine::Mesh cube = engine::make_box({float(x), float(y), float(z)},
                                                           {float(x + 1), float(y + 1), float(z + 1)});
                const auto base = std::uint32_t(m.vertex_count());
                for (std::size_t v = 0; v < cube.vertex_count(); ++v) m.add_vertex({cube.x[v], cube.y[v], cube.z[v]});
                for (std::size_t t = 0; t < cube.triangle_count(); ++t)
                    m.add_triangle(base + cube.indices[3 * t], base + cube.indices[3 * t + 1], base + cube.indices[3 * t + 2]);
            }
    m.compute_bounds();
    return m;
}

}  // namespace arbor::testing
