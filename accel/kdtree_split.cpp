#include "accel/kdtree_split.h"

#include "accel/kdtree_clip.h"

#include <algorithm>

namespace arbor::accel::kd {

std::size_t NodeWork::bytes() const {
    std::size_t b = ids.capacity() * sizeof(std::uint32_t) + boxes.capacity() * sizeof(Bounds);
    for (const auto& e : events) b += e.capacity() * sizeof(Event);
    return b;
}

namespace {
void add_axis_events(std::vector<Event>& out, const Bounds& b, int axis, std::uint32_t local) {
    if (b.lo[axis] == b.hi[axis]) {
        out.push_back(make_event(b.lo[axis], event_planar, local));
    } else {
        out.push_back(make_event(b.lo[axis], event_start, local));
        out.push_back(make_event(b.hi[axis], event_end, local));
    }
}

/// Merges the sorted `extra` into the sorted `v` in place (v grows by extra.size()).
void merge_into(std::vector<Event>& v, const std::vector<Event>& extra) {
    if (extra.empty()) return;
    std::size_t i = v.size(), j = extra.size();
    v.resize(v.size() + extra.size());
    std::size_t out = v.size();
    while (j > 0) {
        if (i > 0 && v[i - 1] > extra[j - 1]) v[--out] = v[--i];
        else v[--out] = extra[--j];
    }
}
}  // namespace

void add_events(NodeWork& w, const Bounds& b, std::uint32_t local) {
    for (int k = 0; k < 3; ++k) add_axis_events(w.events[k], b, k, local);
}

void sort_events(NodeWork& w) {
    for (auto& e : w.events) std::sort(e.begin(), e.end());
}

Split find_split(const NodeWork& w, const SahCosts& costs) {
    Split best;
    const std::size_t n = w.size();
    if (n == 0) return best;
    double ext[3];
    for (int k = 0; k < 3; ++k) ext[k] = double(w.box.hi[k]) - double(w.box.lo[k]);
    const double area = 2.0 * (ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0]);
    if (!(area > 0.0) || !std::isfinite(area)) return best;
    const double inv_area = 1.0 / area;
    for (int k = 0; k < 3; ++k) {
        const float lo = w.box.lo[k], hi = w.box.hi[k];
        if (!(lo < hi)) continue;
        // Area of a child box whose extent along k is x: 2 * (cap + x * per).
        const double cap = ext[(k + 1) % 3] * ext[(k + 2) % 3];
        const double per = ext[(k + 1) % 3] + ext[(k + 2) % 3];
        const std::uint32_t lo_key = float_key(lo), hi_key = float_key(hi);
        const std::vector<Event>& ev = w.events[k];
        std::size_t nl = 0, nr = n;
        std::size_t i = 0;
        while (i < ev.size()) {
            const std::uint32_t pk = event_pos_key(ev[i]);
            std::size_t counts[3] = {0, 0, 0};  // end, planar, start at this position
            while (i < ev.size() && event_pos_key(ev[i]) == pk) ++counts[event_type(ev[i++])];
            const std::size_t np = counts[event_planar];
            nr -= np + counts[event_end];
            if (pk > lo_key && pk < hi_key) {
                const double p = key_float(pk);
                const double al = 2.0 * (cap + (p - lo) * per) * inv_area;
                const double ar = 2.0 * (cap + (hi - p) * per) * inv_area;
                const auto cost = [&](std::size_t l, std::size_t r) {
                    const double c = costs.traversal + costs.intersection * (al * double(l) + ar * double(r));
                    return (l == 0 || r == 0) ? c * costs.empty_factor : c;
                };
                const double cl = cost(nl + np, nr), cr = cost(nl, nr + np);
                const bool left = cl <= cr;
                const double c = left ? cl : cr;
                if (best.axis < 0 || c < best.cost) best = {k, key_float(pk), left, c};
            }
            nl += np + counts[event_start];
        }
    }
    return best;
}

void split_node(const NodeWork& w, const Split& s, const BuildTriangles& tris, bool perfect_splits, NodeWork& left,
                NodeWork& right) {
    const int k = s.axis;
    const float p = s.pos;
    const std::size_t n = w.size();
    left = NodeWork{};
    right = NodeWork{};
    left.box = right.box = w.box;
    left.box.hi[k] = p;
    right.box.lo[k] = p;

    // side: bit 0 left, bit 1 right, bit 2 straddles (its events are regenerated from new bounds).
    std::vector<std::uint8_t> side(n);
    std::vector<std::uint32_t> straddlers;
    for (std::size_t i = 0; i < n; ++i) {
        const Bounds& b = w.boxes[i];
        if (b.lo[k] == p && b.hi[k] == p) side[i] = s.planar_left ? 1 : 2;
        else if (b.hi[k] <= p) side[i] = 1;
        else if (b.lo[k] >= p) side[i] = 2;
        else side[i] = 4, straddlers.push_back(std::uint32_t(i));
    }
    std::vector<Bounds> lbox(straddlers.size()), rbox(straddlers.size());
    for (std::size_t j = 0; j < straddlers.size(); ++j) {
        const std::uint32_t i = straddlers[j];
        const Bounds& b = w.boxes[i];
        if (perfect_splits) {
            const std::uint32_t id = w.ids[i];
            const Vec3f a = tris.corner(id, 0), bb = tris.corner(id, 1), c = tris.corner(id, 2);
            lbox[j] = clip_triangle_bounds(a, bb, c, b, left.box, k);
            rbox[j] = clip_triangle_bounds(a, bb, c, b, right.box, k);
            // Both empty cannot happen for a triangle that meets the node; keep it safe anyway.
            if (lbox[j].empty() && rbox[j].empty()) lbox[j] = intersect(b, left.box), rbox[j] = intersect(b, right.box);
        } else {
            lbox[j] = intersect(b, left.box);
            rbox[j] = intersect(b, right.box);
        }
        side[i] = std::uint8_t(4 | (lbox[j].empty() ? 0 : 1) | (rbox[j].empty() ? 0 : 2));
    }

    // Children's triangle lists in the parent's order: local numbers stay monotone, so filtered
    // events stay sorted.
    std::vector<std::uint32_t> lmap(n), rmap(n);
    std::size_t nl = 0, nr = 0;
    for (std::size_t i = 0; i < n; ++i) nl += side[i] & 1, nr += (side[i] >> 1) & 1;
    left.ids.reserve(nl), left.boxes.reserve(nl);
    right.ids.reserve(nr), right.boxes.reserve(nr);
    for (std::size_t i = 0, j = 0; i < n; ++i) {
        const bool st = side[i] & 4;
        if (side[i] & 1) {
            lmap[i] = std::uint32_t(left.ids.size());
            left.ids.push_back(w.ids[i]);
            left.boxes.push_back(st ? lbox[j] : w.boxes[i]);
        }
        if (side[i] & 2) {
            rmap[i] = std::uint32_t(right.ids.size());
            right.ids.push_back(w.ids[i]);
            right.boxes.push_back(st ? rbox[j] : w.boxes[i]);
        }
        j += st;
    }

    std::vector<Event> extra;
    for (int a = 0; a < 3; ++a) {
        std::vector<Event>& le = left.events[a];
        std::vector<Event>& re = right.events[a];
        le.reserve(2 * nl);
        re.reserve(2 * nr);
        for (const Event e : w.events[a]) {
            const std::uint32_t i = event_local(e);
            const Event head = e & ~Event(0x3FFFFFFFu);
            if (side[i] == 1) le.push_back(head | lmap[i]);
            else if (side[i] == 2) re.push_back(head | rmap[i]);
        }
        for (int child = 0; child < 2; ++child) {
            extra.clear();
            for (std::size_t j = 0; j < straddlers.size(); ++j) {
                const std::uint32_t i = straddlers[j];
                if (!(side[i] & (1 << child))) continue;
                add_axis_events(extra, child == 0 ? lbox[j] : rbox[j], a, child == 0 ? lmap[i] : rmap[i]);
            }
            std::sort(extra.begin(), extra.end());
            merge_into(child == 0 ? le : re, extra);
        }
    }
}

}  // namespace arbor::accel::kd
