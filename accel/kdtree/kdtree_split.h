#pragma once
/// One step of the kd-tree build: the SAH split search over sorted events and the split of a node's
/// triangles and events into its two children, in O(N) per node after one sort at the root.
/// See "On building fast kd-Trees for Ray Tracing, and on doing that in O(N log N)", I. Wald and
/// V. Havran, 2006.
#include "accel/core/geometry.h"

#include <bit>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace arbor::accel::kd {

/// An event is one 64-bit key: the plane position mapped to an order-preserving uint32 (high half)
/// and (type << 30 | local triangle number) (low half), so integer order is Wald-Havran's order
/// (position, then end < planar < start), made total by the triangle number.
using Event = std::uint64_t;
enum EventType : std::uint32_t { event_end = 0, event_planar = 1, event_start = 2 };
inline constexpr Event event_local_mask = 0x3FFFFFFFu;

/// Order-preserving map of a float (not NaN; -0 is treated as +0) to uint32.
inline std::uint32_t float_key(float f) {
    const std::uint32_t u = std::bit_cast<std::uint32_t>(f + 0.0f);  // -0 + 0 = +0
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
inline float key_float(std::uint32_t k) { return std::bit_cast<float>((k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k); }
inline Event make_event(float pos, EventType type, std::uint32_t local) {
    return (std::uint64_t(float_key(pos)) << 32) | (std::uint32_t(type) << 30) | local;
}
inline std::uint32_t event_pos_key(Event e) { return std::uint32_t(e >> 32); }
inline EventType event_type(Event e) { return EventType((std::uint32_t(e) >> 30) & 3u); }
inline std::uint32_t event_local(Event e) { return std::uint32_t(e & event_local_mask); }

/// The triangles of one node: their numbers (index into the build's finite triangles), their
/// clipped bounds inside the node, and per axis their events, sorted. Big nodes are split by
/// binning and carry no events; allocate_events + make_events give a node its sorted events.
class NodeWork {
public:
    Bounds box;

    NodeWork() = default;
    /// Room for n triangles (and, with events, 2n events per axis).
    NodeWork(std::size_t n, bool with_events);
    std::size_t size() const { return n_; }
    std::size_t bytes() const { return bytes_; }
    bool has_events() const { return events_[0] != nullptr; }
    void allocate_events();
    std::uint32_t* ids() const { return ids_; }
    Bounds* boxes() const { return boxes_; }
    /// Events of `axis`; set_event_count after writing them.
    Event* events(int axis) const { return events_[axis]; }
    std::span<const Event> event_span(int axis) const { return {events_[axis], counts_[axis]}; }
    void set_event_count(int axis, std::size_t c) { counts_[axis] = c; }

private:
    std::unique_ptr<std::byte[]> mem_, event_mem_;
    std::size_t n_ = 0, bytes_ = 0;
    std::uint32_t* ids_ = nullptr;
    Bounds* boxes_ = nullptr;
    Event* events_[3] = {nullptr, nullptr, nullptr};
    std::size_t counts_[3] = {0, 0, 0};
};

/// Writes the events of a triangle with clipped bounds `b` and local number `local` on `axis`
/// (one planar event where b is flat, else a start and an end); returns the new end.
inline Event* put_events(Event* out, const Bounds& b, int axis, std::uint32_t local) {
    if (b.lo[axis] == b.hi[axis]) {
        *out++ = make_event(b.lo[axis], event_planar, local);
    } else {
        *out++ = make_event(b.lo[axis], event_start, local);
        *out++ = make_event(b.hi[axis], event_end, local);
    }
    return out;
}

struct SahCosts {
    double traversal = 1.0;    ///< K_T
    double intersection = 1.0; ///< K_I
    double empty_factor = 0.8; ///< cost multiplier when one side is empty (Wald-Havran's lambda)
};

/// A split plane: axis, position, where triangles lying in the plane go, and its SAH cost
/// (relative to the node's area: K_T + K_I * (A_L N_L + A_R N_R) / A, times the empty factor).
struct Split {
    int axis = -1;  ///< -1: no candidate plane inside the node
    float pos = 0.0f;
    bool planar_left = true;
    double cost = 0.0;
};

/// Fills and sorts the events of a node that has none (from its clipped bounds).
void make_events(NodeWork& w);

/// Number of bins of the binned split search used for big nodes.
inline constexpr int split_bins = 256;
/// The cheapest of the split_bins - 1 equally spaced planes of `axis` inside the node box, from
/// bin counts of the triangles' clipped bounds (an estimate for big nodes: O(N), no events).
Split find_split_binned(const NodeWork& w, int axis, const SahCosts& costs);

/// The cheapest plane of `axis` strictly inside the node box, by one sweep over its events.
/// Deterministic: the first plane (ascending position) of least cost wins.
Split find_split_on_axis(const NodeWork& w, int axis, const SahCosts& costs);
/// The cheapest plane over the three axes (the lower axis wins a tie).
Split find_split(const NodeWork& w, const SahCosts& costs);

/// The finite triangles of the build, as the builder reads them.
struct BuildTriangles {
    std::vector<Vec3f> v;  ///< 3 corners per triangle
    Vec3f corner(std::uint32_t id, int k) const { return v[3 * std::size_t(id) + k]; }
};

/// Per-thread temporaries of split_node, reused from node to node.
struct SplitScratch {
    std::vector<std::uint8_t> side;
    std::vector<std::uint32_t> lmap, rmap, straddlers;
    std::vector<Bounds> lbox, rbox;
    std::vector<Event> extra;
    std::size_t bytes() const;
};

/// Splits `w` at `s` into `left` and `right` (both overwritten). Triangles entirely on one side go
/// there (touching the plane counts as that side); triangles lying in the plane go to the side
/// `s.planar_left` says; the others are clipped to each child (perfect splits: the triangle itself,
/// else its bounds) and go to every child they still meet, with new events merged in (children of
/// a node without events get none).
void split_node(const NodeWork& w, const Split& s, const BuildTriangles& tris, bool perfect_splits,
                SplitScratch& scratch, NodeWork& left, NodeWork& right);

}  // namespace arbor::accel::kd
