/// The cost integrator: what each camera ray costs the structure. Every camera batch is traced
/// twice: once on the renderer's normal path (timed as primary rays, so the summary's Mrays/s is
/// the structure's real speed on these rays) and once on the structure's counting loop, the
/// counted mode of the benchmarks (TraceRequest::counters, its own instantiation: the timed paths
/// carry no counter). The film's first two sums hold the nodes visited and the triangles tested;
/// the renderer writes their per-pixel means as the layers `nodes` and `tris`.
///
/// What the counts mean, per structure, so that they compare (accel.h, TraceCounters): a node is
/// a traversal step of the structure's scalar reference walk, the tree of the SAH cost model.
/// - BVHs (bvh-median, bvh-sah, lbvh): each binary interior node whose two child boxes the ray
///   tested, and each leaf it entered (the scene box test before the root is not counted).
/// - kd-tree: each interior node whose split plane the ray was compared with (on every descent
///   from the root or from a rope's target, and around edges and corners passed near) and each
///   leaf entered, empty leaves included.
/// - brute: one node (the single leaf holding every triangle); every triangle is tested.
/// Rays that cannot be traced (NaN, zero direction) cost nothing.
#include "engine/integrator.h"

#include <stdexcept>

namespace arbor::engine {

namespace {

class CostIntegrator final : public Integrator {
public:
    void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const override {
        std::vector<accel::Ray> rays;
        std::vector<accel::Hit> hits;
        std::vector<accel::TraceCounters> cost;
        std::vector<PathState> paths;
        const int spp = ctx.settings.spp, pass = samples_per_pass(film.tile, spp);
        for (int s0 = 0; s0 < spp; s0 += pass) {
            camera_batch(ctx, film.tile, s0, std::min(spp, s0 + pass), rays, paths);
            hits.resize(rays.size());
            cost.resize(rays.size());
            tracer.closest(rays, hits, RenderRayKind::primary);
            if (!tracer.counted(rays, hits, cost))
                throw std::logic_error("cost integrator: the structure cannot count (build it with its scalar layout)");
            for (std::size_t i = 0; i < rays.size(); ++i)
                film.color[paths[i].pixel] += Vec3f{float(cost[i].nodes_visited), float(cost[i].triangles_tested), 0.0f};
        }
    }
};

}  // namespace

std::unique_ptr<Integrator> make_cost_integrator() { return std::make_unique<CostIntegrator>(); }

}  // namespace arbor::engine
