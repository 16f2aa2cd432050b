#include "engine/renderer.h"

#include "accel/util/timer.h"
#include "engine/integrator.h"
#include "engine/progress.h"

#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <stdexcept>

namespace arbor::engine {

std::vector<std::string> channel_names(const Layers& layers) {
    std::vector<std::string> n{"R", "G", "B"};
    if (layers.depth) n.push_back("Z");
    if (layers.normal) n.insert(n.end(), {"N.X", "N.Y", "N.Z"});
    if (layers.albedo) n.insert(n.end(), {"A.R", "A.G", "A.B"});
    return n;
}

std::vector<std::string> channel_names(const RenderPlan& plan) {
    if (plan.integrator == IntegratorKind::cost) return {"nodes", "tris"};
    return channel_names(plan.layers);
}

namespace {

/// Writes the averages of a finished tile into the image.
void store_tile(const TileFilm& film, int spp, const Layers& layers, Image& img) {
    const float inv = 1.0f / float(spp);
    const Tile& t = film.tile;
    const int z = img.channel("Z"), nx = img.channel("N.X"), ar = img.channel("A.R");
    const int colour = img.channel("R") == 0 ? 3 : 2;  // R, G, B; or the cost integrator's nodes, tris
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            const std::size_t i = std::size_t((y - t.y0) * t.width() + (x - t.x0));
            for (int c = 0; c < colour; ++c) img.at(c, x, y) = film.color[i][c] * inv;
            if (layers.depth) img.at(z, x, y) = film.depth[i];
            for (int c = 0; layers.normal && c < 3; ++c) img.at(nx + c, x, y) = film.normal[i][c] * inv;
            for (int c = 0; layers.albedo && c < 3; ++c) img.at(ar + c, x, y) = film.albedo[i][c] * inv;
        }
}

}  // namespace

namespace {

Image render_view(const Scene& scene, const Camera& view, const LightSet& lights, const RenderPlan& plan,
                  const accel::Accel& accel, const RenderSettings& set, RenderStats* stats, TileSource* tiles) {
    if (set.width < 1 || set.height < 1 || set.spp < 1 || set.tile < 1)
        throw std::invalid_argument("render: width, height, spp and tile must be positive");
    const accel::Timer timer;
    Camera camera = view;
    camera.prepare(set.width, set.height);
    const RenderContext ctx(scene, camera, lights, plan, set);
    const auto integrator = make_integrator(plan.integrator);
    Image img(set.width, set.height, channel_names(plan));

    const TileGrid grid{set.width, set.height, set.tile};
    Progress progress("rendering", grid.count(), set.progress && (!tiles || tiles->shows_progress()),
                      tiles && tiles->progress_to_terminal());
    tbb::enumerable_thread_specific<Tracer> tracers([&] { return Tracer(accel); });
    auto render_tile = [&](int index) {
        Tile tile;
        grid.bounds(index, tile.x0, tile.y0, tile.x1, tile.y1);
        TileFilm film(tile, plan.layers);
        integrator->render_tile(ctx, tracers.local(), film);
        store_tile(film, set.spp, plan.layers, img);
    };
    if (tiles) {
        tiles->run(grid, img, progress, render_tile);
    } else {
        tbb::parallel_for(tbb::blocked_range2d<int>(0, grid.rows(), 1, 0, grid.columns(), 1),
                          [&](const tbb::blocked_range2d<int>& r) {
                              for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
                                  for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
                                      // A render inside a cancelled task group (the viewer's page
                                      // moved or left) stops at the next tile: one thread may own a
                                      // long range of tiles.
                                      if (tbb::is_current_task_group_canceling()) return;
                                      render_tile(ty * grid.columns() + tx);
                                      progress.tick();
                                  }
                          });
    }
    RenderStats local;
    local.seconds = timer.seconds();
    local.threads = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    for (const Tracer& t : tracers)
        for (std::size_t k = 0; k < render_ray_kind_count; ++k) {
            local.rays[k] += t.counts[k];
            local.trace_seconds[k] += t.seconds[k];
        }
    if (tiles) tiles->gather(local);  // collective over the processes of the frame: always called
    if (stats) *stats = local;
    return img;
}

}  // namespace

Image render(const Scene& scene, const LightSet& lights, const RenderPlan& plan, const accel::Accel& accel,
             const RenderSettings& set, RenderStats* stats, TileSource* tiles) {
    return render_view(scene, scene.camera, lights, plan, accel, set, stats, tiles);
}

Image render(const Scene& scene, const Camera& camera, const LightSet& lights, const RenderPlan& plan,
             const accel::Accel& accel, const RenderSettings& set, RenderStats* stats) {
    return render_view(scene, camera, lights, plan, accel, set, stats, nullptr);
}

Image render(const Scene& scene, const accel::Accel& accel, const RenderSettings& set, RenderStats* stats) {
    const LightSet lights(scene);
    const RenderPlan plan = make_plan(scene, lights, set);
    return render(scene, lights, plan, accel, set, stats);
}

}  // namespace arbor::engine
