#pragma once
/// One step of the kd-tree build: the SAH split search over sorted events and the split of a node's
/// triangles and events into its two children, in O(N) per node after one sort at the root.
/// See "On building fast kd-Trees for Ray Tracing, and on doing that in O(N log N)", I. Wald and
/// V. Havran, 2006.
#include "accel/geometry.h"

#include <bit>
#include <cstdint>
#include <vector>

namespace arbor::accel::kd {

/// An event is one 64-bit key: the plane position mapped to an order-preserving uint32 (high half)
/// and (type << 30 | local triangle number) (low half), so integer order is Wald-Havran's order
/// (position, then end < planar < start), made total by the triangle number.
using Event = std::uint64_t;
enum EventType : std::uint32_t { event_end = 0, event_planar = 1, event_start = 2 };

/// Order-preserving map of a float (not NaN; -0 is treated as +0) to uint32.
inline std::uint32_t float_key(float f) {
    std::uint32_t u = std::bit_cast<std::uint32_t>(f + 0.0f);  // -0 + 0 = +0
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
inline float key_float(std::uint32_t k) { return std::bit_cast<float>((k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k); }
inline Event make_event(float pos, EventType type, std::uint32_t local) {
    return (std::uint64_t(float_key(pos)) << 32) | (std::uint32_t(type) << 30) | local;
}
inline std::uint32_t event_pos_key(Event e) { return std::uint32_t(e >> 32); }
inline EventType event_type(Event e) { return EventType((std::uint32_t(e) >> 30) & 3u); }
inline std::uint32_t event_local(Event e) { return std::uint32_t(e) & 0x3FFFFFFFu; }

/// The triangles of one node: their numbers (index into the build's finite triangles), their
/// clipped bounds inside the node, and per axis their events, sorted.
struct NodeWork {
    Bounds box;
    std::vector<std::uint32_t> ids;
    std::vector<Bounds> boxes;
    std::vector<Event> events[3];

    std::size_t size() const { return ids.size(); }
    std::size_t bytes() const;
};

/// Appends the events of a triangle with clipped bounds `b` and local number `local` (one planar
/// event on axes where b is flat, else a start and an end).
void add_events(NodeWork& w, const Bounds& b, std::uint32_t local);
/// Sorts the three event lists (the root's; children keep theirs sorted by construction).
void sort_events(NodeWork& w);

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

/// The cheapest plane strictly inside the node box, found by one sweep over each axis' events.
/// Deterministic: the first plane (axis 0..2, ascending position) of least cost wins.
Split find_split(const NodeWork& w, const SahCosts& costs);

/// The finite triangles of the build, as the builder reads them.
struct BuildTriangles {
    std::vector<Vec3f> v;  ///< 3 corners per triangle
    Vec3f corner(std::uint32_t id, int k) const { return v[3 * std::size_t(id) + k]; }
};

/// Splits `w` at `s` into `left` and `right` (both overwritten). Triangles entirely on one side go
/// there (touching the plane counts as that side); triangles lying in the plane go to the side
/// `s.planar_left` says; the others are clipped to each child (perfect splits: the triangle itself,
/// else its bounds) and go to every child they still meet, with new events merged in.
void split_node(const NodeWork& w, const Split& s, const BuildTriangles& tris, bool perfect_splits, NodeWork& left,
                NodeWork& right);

}  // namespace arbor::accel::kd
