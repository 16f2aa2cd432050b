/// arbor::Scene's winding numbers, inside by method, signed distances and closed(): the winding
/// tree is made by the first winding query after a build (a plain build and its traces make
/// nothing for it), closed() on its first call after add_mesh.
#include "accel/core/closed_mesh.h"
#include "accel/interface/inside.h"
#include "api/batch.h"
#include "api/point_order.h"

#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace arbor {

const accel::WindingTree& Scene::Impl::winding_tree(CallArena& call) {
    const accel::Accel& a = structure();
    if (!winding_ready.load(std::memory_order_acquire)) {
        const std::lock_guard lock(lazy_mutex);
        if (!winding_ready.load(std::memory_order_relaxed)) {
            // On the call's threads: the dipoles of the leaves are made in parallel.
            call.execute([&] { winding = a.make_winding_tree(mesh.view()); });
            winding_ready.store(true, std::memory_order_release);
        }
    }
    return *winding;
}

namespace {

void check_winding(const WindingOptions& o, const char* fn) {
    if (!(o.beta > 1.0))
        throw Error(Error::Kind::invalid_argument,
                    std::string(fn) + ": beta must be > 1 (+inf: exact), got " + std::to_string(o.beta));
}

void check_method(InsideMethod m, const char* fn) {
    if (m != InsideMethod::parity && m != InsideMethod::winding)
        throw Error(Error::Kind::invalid_argument, std::string(fn) + ": unknown method " + std::to_string(int(m)) +
                                                       " (expected InsideMethod::parity or InsideMethod::winding)");
}

/// Winding numbers of points [begin, end) into out[0 ..): the exact sum, or the structure's tree.
class WindingSource {
public:
    WindingSource(Scene::Impl& s, CallArena& call, const WindingOptions& o, const char* fn) : beta_(o.beta) {
        // The tree is made over the meshes as added; placed copies would need a tree of their own.
        if (!s.instances.empty())
            throw Error(Error::Kind::invalid_argument,
                        std::string(fn) + ": winding numbers are not offered on a scene with instances yet "
                                          "(inside and signed_distance by parity are)");
        if (o.exact) {
            s.structure();  // a query builds a scene never built, whatever it asks
            exact_ = accel::make_exact_winding(s.mesh.view());
            tree_ = exact_.get();
        } else {
            tree_ = &s.winding_tree(call);
        }
    }
    void run(std::span<const accel::Vec3f> points, std::span<double> out) const {
        tree_->winding_numbers(points, beta_, out);
    }

private:
    double beta_;
    std::unique_ptr<accel::WindingTree> exact_;
    const accel::WindingTree* tree_ = nullptr;
};

/// What inside and signed_distance do first: check `method` (and `winding` for the winding
/// method), build the scene if it never was, and make the winding source (null for the parity).
std::unique_ptr<WindingSource> method_source(Scene::Impl& s, CallArena& call, InsideMethod method,
                                             const WindingOptions& winding, const char* fn) {
    check_method(method, fn);
    if (method == InsideMethod::winding) check_winding(winding, fn);
    s.structure();
    if (method != InsideMethod::winding) return nullptr;
    return std::make_unique<WindingSource>(s, call, winding, fn);
}

/// inside[i] for points [b, e) by `method` into `res` (one byte per point).
void inside_chunk(const Scene::Impl& s, const accel::Accel& a, const WindingSource* w, std::span<const accel::Vec3f> in,
                  std::span<std::uint8_t> res) {
    if (!w) {
        accel::inside_points(a, s.world_bounds(), in, res);
        return;
    }
    thread_local std::vector<double> wn;
    wn.resize(in.size());
    w->run(in, wn);
    for (std::size_t i = 0; i < in.size(); ++i) res[i] = wn[i] >= 0.5;  // NaN (non-finite point): outside
}

}  // namespace

void Scene::winding_number(const PointArrays& points, double* out, const WindingOptions& winding,
                           const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "winding_number");
        check_points(points, out, "winding_number");
        check_winding(winding, "winding_number");
        const WindingSource w(*impl_, arena, winding, "winding_number");
        for_chunks(arena, points.count, point_chunk, [&](std::size_t b, std::size_t e) {
            w.run(load_points(points, b, e), std::span<double>(out + b, e - b));
        });
    });
}

void Scene::inside(const PointArrays& points, bool* inside, const QueryOptions& options) const {
    this->inside(points, inside, InsideMethod::parity, {}, options);
}

void Scene::inside(const PointArrays& points, bool* inside, InsideMethod method, const WindingOptions& winding,
                   const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "inside");
        check_points(points, inside, "inside");
        const std::unique_ptr<WindingSource> w = method_source(*impl_, arena, method, winding, "inside");
        const accel::Accel& a = impl_->structure();
        for_chunks(arena, points.count, point_chunk, [&](std::size_t b, std::size_t e) {
            const auto in = load_points(points, b, e);
            thread_local std::vector<std::uint8_t> res;
            res.resize(in.size());
            inside_chunk(*impl_, a, w.get(), in, res);
            for (std::size_t i = b; i < e; ++i) inside[i] = res[i - b] != 0;
        });
    });
}

void Scene::signed_distance(const PointArrays& points, float* out, InsideMethod method,
                            const WindingOptions& winding, const QueryOptions& options) const {
    guarded([&] {
        CallArena arena(*impl_, options, "signed_distance");
        check_points(points, out, "signed_distance");
        const std::unique_ptr<WindingSource> w = method_source(*impl_, arena, method, winding, "signed_distance");
        const accel::Accel& a = impl_->structure();
        // Visited along a curve, as closest_point does (api/point_order.h): the answers do not
        // depend on the order.
        const std::vector<std::uint32_t> order = spatial_order(points, arena);
        for_chunks(arena, points.count, point_chunk, [&](std::size_t b, std::size_t e) {
            const auto in = load_points(points, order, b, e);
            thread_local std::vector<accel::PointHit> near;
            thread_local std::vector<std::uint8_t> res;
            near.resize(in.size());
            res.resize(in.size());
            a.closest_points(in, std::numeric_limits<float>::infinity(), near);
            inside_chunk(*impl_, a, w.get(), in, res);
            for (std::size_t k = b; k < e; ++k) {
                const float d = near[k - b].distance;  // +inf: nothing found (empty scene, non-finite point)
                out[point_at(order, k)] = res[k - b] && std::isfinite(d) ? -d : d;
            }
        });
    });
}

bool Scene::closed() const {
    return guarded([&] {
        int state = impl_->closed_state.load(std::memory_order_acquire);
        if (state < 0) {
            const std::lock_guard lock(impl_->lazy_mutex);
            state = impl_->closed_state.load(std::memory_order_relaxed);
            if (state < 0) {
                state = accel::is_closed_mesh(impl_->mesh.indices) ? 1 : 0;
                impl_->closed_state.store(state, std::memory_order_release);
            }
        }
        return state == 1;
    });
}

std::vector<double> Scene::winding_number(const std::vector<float>& xyz, const WindingOptions& winding,
                                          const QueryOptions& options) const {
    const PointArrays p = packed_points(xyz, "winding_number");
    std::vector<double> out(p.count);
    winding_number(p, out.data(), winding, options);
    return out;
}

std::vector<bool> Scene::inside(const std::vector<float>& xyz, const QueryOptions& options) const {
    return inside(xyz, InsideMethod::parity, {}, options);
}

std::vector<bool> Scene::inside(const std::vector<float>& xyz, InsideMethod method, const WindingOptions& winding,
                                const QueryOptions& options) const {
    const PointArrays p = packed_points(xyz, "inside");
    const std::unique_ptr<bool[]> out(new bool[p.count]);
    inside(p, out.get(), method, winding, options);
    return std::vector<bool>(out.get(), out.get() + p.count);
}

std::vector<float> Scene::signed_distance(const std::vector<float>& xyz, InsideMethod method,
                                          const WindingOptions& winding, const QueryOptions& options) const {
    const PointArrays p = packed_points(xyz, "signed_distance");
    std::vector<float> out(p.count);
    signed_distance(p, out.data(), method, winding, options);
    return out;
}

}  // namespace arbor
