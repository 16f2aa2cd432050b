#include "accel/kdtree/kdtree_split.h"

#include "accel/kdtree/kdtree_clip.h"

#include <algorithm>
#include <cmath>

namespace arbor::accel::kd {

namespace {
constexpr std::size_t align8(std::size_t b) { return (b + 7) & ~std::size_t(7); }

/// Merges sorted extra[0, x) into sorted v[0, f), in place (v has room for f + x).
void merge_back(Event* v, std::size_t f, const Event* extra, std::size_t x) {
    std::size_t out = f + x;
    while (x > 0) {
        if (f > 0 && v[f - 1] > extra[x - 1]) v[--out] = v[--f];
        else v[--out] = extra[--x];
    }
}
}  // namespace

NodeWork::NodeWork(std::size_t n, bool with_events) : n_(n) {
    // One allocation: ids, boxes, then (with events) 2n + 1 events per axis, the extra slot being
    // slack for branchless writes.
    const std::size_t ids_bytes = align8(n * sizeof(std::uint32_t)), box_bytes = align8(n * sizeof(Bounds));
    const std::size_t ev_bytes = with_events ? 3 * (2 * n + 1) * sizeof(Event) : 0;
    bytes_ = ids_bytes + box_bytes + ev_bytes;
    mem_ = std::make_unique_for_overwrite<std::byte[]>(bytes_);
    ids_ = reinterpret_cast<std::uint32_t*>(mem_.get());
    boxes_ = reinterpret_cast<Bounds*>(mem_.get() + ids_bytes);
    if (with_events)
        for (int a = 0; a < 3; ++a) events_[a] = reinterpret_cast<Event*>(mem_.get() + ids_bytes + box_bytes) + a * (2 * n + 1);
}

void NodeWork::allocate_events() {
    const std::size_t per_axis = 2 * n_ + 1;
    event_mem_ = std::make_unique_for_overwrite<std::byte[]>(3 * per_axis * sizeof(Event));
    bytes_ += 3 * per_axis * sizeof(Event);
    for (int a = 0; a < 3; ++a) events_[a] = reinterpret_cast<Event*>(event_mem_.get()) + a * per_axis;
}

void make_events(NodeWork& w) {
    if (!w.has_events()) w.allocate_events();
    for (int k = 0; k < 3; ++k) {
        Event* e = w.events(k);
        for (std::size_t i = 0; i < w.size(); ++i) e = put_events(e, w.boxes()[i], k, std::uint32_t(i));
        w.set_event_count(k, std::size_t(e - w.events(k)));
        std::sort(w.events(k), e);
    }
}

std::size_t SplitScratch::bytes() const {
    return side.capacity() + (lmap.capacity() + rmap.capacity() + straddlers.capacity()) * sizeof(std::uint32_t) +
           (lbox.capacity() + rbox.capacity()) * sizeof(Bounds) + extra.capacity() * sizeof(Event);
}

Split find_split_binned(const NodeWork& w, int k, const SahCosts& costs) {
    Split best;
    const std::size_t n = w.size();
    const float lo = w.box.lo[k], hi = w.box.hi[k];
    if (n == 0 || !(lo < hi)) return best;
    double ext[3];
    for (int j = 0; j < 3; ++j) ext[j] = double(w.box.hi[j]) - double(w.box.lo[j]);
    const double area = 2.0 * (ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0]);
    if (!(area > 0.0) || !std::isfinite(area)) return best;
    const double cap = ext[(k + 1) % 3] * ext[(k + 2) % 3];
    const double per = ext[(k + 1) % 3] + ext[(k + 2) % 3];
    const double scale = 2.0 * costs.intersection / area;
    // starts[b]: triangles whose bounds begin in bin b; ends[b]: end in bin b. Plane b (between bins
    // b - 1 and b) then has sum(starts[< b]) triangles reaching left and sum(ends[>= b]) right.
    std::uint32_t starts[split_bins] = {}, ends[split_bins] = {};
    const double to_bin = double(split_bins) / ext[k];
    const auto bin = [&](float x) {
        const double b = (double(x) - lo) * to_bin;
        return b <= 0.0 ? 0 : (b >= split_bins - 1 ? split_bins - 1 : int(b));
    };
    const Bounds* boxes = w.boxes();
    for (std::size_t i = 0; i < n; ++i) {
        ++starts[bin(boxes[i].lo[k])];
        ++ends[bin(boxes[i].hi[k])];
    }
    std::size_t nl = 0, nr = n;
    for (int b = 1; b < split_bins; ++b) {
        nl += starts[b - 1];
        nr -= ends[b - 1];
        const float p = float(double(lo) + ext[k] * double(b) / split_bins);
        if (!(p > lo && p < hi)) continue;
        const double al = (cap + (double(p) - lo) * per) * scale, ar = (cap + (double(hi) - p) * per) * scale;
        double c = costs.traversal + al * double(nl) + ar * double(nr);
        if (nl == 0 || nr == 0) c *= costs.empty_factor;
        if (best.axis < 0 || c < best.cost) best = {k, p, true, c};
    }
    return best;
}

Split find_split_on_axis(const NodeWork& w, int k, const SahCosts& costs) {
    Split best;
    const std::size_t n = w.size();
    const float lo = w.box.lo[k], hi = w.box.hi[k];
    if (n == 0 || !(lo < hi)) return best;
    double ext[3];
    for (int j = 0; j < 3; ++j) ext[j] = double(w.box.hi[j]) - double(w.box.lo[j]);
    const double area = 2.0 * (ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0]);
    if (!(area > 0.0) || !std::isfinite(area)) return best;
    // A child whose extent along k is x has area 2 * (cap + x * per); costs are relative to `area`.
    const double cap = ext[(k + 1) % 3] * ext[(k + 2) % 3];
    const double per = ext[(k + 1) % 3] + ext[(k + 2) % 3];
    const double scale = 2.0 * costs.intersection / area;
    const std::uint32_t lo_key = float_key(lo), hi_key = float_key(hi);
    const std::span<const Event> ev = w.event_span(k);
    const std::size_t m = ev.size();
    std::size_t nl = 0, nr = n;
    std::size_t i = 0;
    while (i < m) {
        const std::uint32_t pk = event_pos_key(ev[i]);
        // Events at this position: ends, then planars, then starts (their order in the key).
        std::size_t ne = 0, np = 0, nst = 0;
        do {
            const EventType t = event_type(ev[i]);
            ne += t == event_end;
            np += t == event_planar;
            nst += t == event_start;
        } while (++i < m && event_pos_key(ev[i]) == pk);
        nr -= np + ne;
        if (pk > lo_key && pk < hi_key) {
            const double p = key_float(pk);
            const double al = (cap + (p - lo) * per) * scale, ar = (cap + (hi - p) * per) * scale;
            const auto cost = [&](std::size_t l, std::size_t r) {
                const double c = costs.traversal + al * double(l) + ar * double(r);
                return (l == 0 || r == 0) ? c * costs.empty_factor : c;
            };
            double c = cost(nl + np, nr);
            bool left = true;
            if (np != 0) {
                const double cr = cost(nl, nr + np);
                if (cr < c) c = cr, left = false;
            }
            if (best.axis < 0 || c < best.cost) best = {k, key_float(pk), left, c};
        }
        nl += np + nst;
    }
    return best;
}

Split find_split(const NodeWork& w, const SahCosts& costs) {
    Split best;
    for (int k = 0; k < 3; ++k) {
        const Split s = find_split_on_axis(w, k, costs);
        if (s.axis >= 0 && (best.axis < 0 || s.cost < best.cost)) best = s;
    }
    return best;
}

void split_node(const NodeWork& w, const Split& s, const BuildTriangles& tris, bool perfect_splits,
                SplitScratch& sc, NodeWork& left, NodeWork& right) {
    const int k = s.axis;
    const float p = s.pos;
    const std::size_t n = w.size();
    const std::uint32_t* ids = w.ids();
    const Bounds* boxes = w.boxes();
    Bounds lnode = w.box, rnode = w.box;
    lnode.hi[k] = p;
    rnode.lo[k] = p;

    // side: bit 0 left, bit 1 right, bit 2 straddles (its events are regenerated from new bounds).
    sc.side.resize(n);
    sc.straddlers.clear();
    std::uint8_t* side = sc.side.data();
    const std::uint8_t planar_side = s.planar_left ? 1 : 2;
    for (std::size_t i = 0; i < n; ++i) {
        const float blo = boxes[i].lo[k], bhi = boxes[i].hi[k];
        if (blo == p && bhi == p) side[i] = planar_side;
        else if (bhi <= p) side[i] = 1;
        else if (blo >= p) side[i] = 2;
        else side[i] = 4, sc.straddlers.push_back(std::uint32_t(i));
    }
    const std::size_t ns = sc.straddlers.size();
    sc.lbox.resize(ns);
    sc.rbox.resize(ns);
    for (std::size_t j = 0; j < ns; ++j) {
        const std::uint32_t i = sc.straddlers[j];
        const Bounds& b = boxes[i];
        Bounds& lb = sc.lbox[j];
        Bounds& rb = sc.rbox[j];
        if (perfect_splits) {
            const std::uint32_t id = ids[i];
            const Vec3f a = tris.corner(id, 0), bb = tris.corner(id, 1), c = tris.corner(id, 2);
            lb = clip_triangle_bounds(a, bb, c, b, lnode, k);
            rb = clip_triangle_bounds(a, bb, c, b, rnode, k);
            // Both empty cannot happen for a triangle that meets the node; stay safe anyway.
            if (lb.empty() && rb.empty()) lb = intersect(b, lnode), rb = intersect(b, rnode);
        } else {
            lb = intersect(b, lnode);
            rb = intersect(b, rnode);
        }
        side[i] = std::uint8_t(4 | (lb.empty() ? 0 : 1) | (rb.empty() ? 0 : 2));
    }

    // Children's triangle lists in the parent's order: local numbers stay monotone, so filtered
    // events stay sorted.
    std::size_t nl = 0, nr = 0;
    for (std::size_t i = 0; i < n; ++i) nl += side[i] & 1, nr += (side[i] >> 1) & 1;
    const bool events = w.has_events();
    left = NodeWork(nl, events);
    right = NodeWork(nr, events);
    left.box = lnode;
    right.box = rnode;
    sc.lmap.resize(n);
    sc.rmap.resize(n);
    std::uint32_t* lmap = sc.lmap.data();
    std::uint32_t* rmap = sc.rmap.data();
    std::uint32_t* lids = left.ids();
    std::uint32_t* rids = right.ids();
    Bounds* lboxes = left.boxes();
    Bounds* rboxes = right.boxes();
    std::uint32_t cl = 0, cr = 0;
    for (std::size_t i = 0, j = 0; i < n; ++i) {
        const std::uint8_t sd = side[i];
        const bool st = sd & 4;
        if (sd & 1) {
            lmap[i] = cl;
            lids[cl] = ids[i];
            lboxes[cl++] = st ? sc.lbox[j] : boxes[i];
        }
        if (sd & 2) {
            rmap[i] = cr;
            rids[cr] = ids[i];
            rboxes[cr++] = st ? sc.rbox[j] : boxes[i];
        }
        j += st;
    }

    for (int a = 0; a < 3 && events; ++a) {
        // Events of one-sided triangles keep their order; writes are branchless (each buffer has
        // a slot of slack at the end).
        Event* lp = left.events(a);
        Event* rp = right.events(a);
        for (const Event e : w.event_span(a)) {
            const std::uint32_t i = event_local(e);
            const Event head = e & ~event_local_mask;
            const std::uint8_t sd = side[i];
            *lp = head | lmap[i];
            lp += sd == 1;
            *rp = head | rmap[i];
            rp += sd == 2;
        }
        for (int child = 0; child < 2; ++child) {
            NodeWork& cw = child == 0 ? left : right;
            const std::size_t filtered = std::size_t((child == 0 ? lp : rp) - cw.events(a));
            sc.extra.resize(2 * ns);
            Event* x = sc.extra.data();
            for (std::size_t j = 0; j < ns; ++j) {
                const std::uint32_t i = sc.straddlers[j];
                if (side[i] & (1 << child))
                    x = put_events(x, child == 0 ? sc.lbox[j] : sc.rbox[j], a, child == 0 ? lmap[i] : rmap[i]);
            }
            const std::size_t added = std::size_t(x - sc.extra.data());
            std::sort(sc.extra.data(), x);
            merge_back(cw.events(a), filtered, sc.extra.data(), added);
            cw.set_event_count(a, filtered + added);
        }
    }
}

}  // namespace arbor::accel::kd
