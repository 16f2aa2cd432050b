// The renderer's tile seam (engine/tile_source.h), as one rank of `mpirun arbor render` uses it:
// a source that renders only some tiles, in another order, gives exactly those tiles of the
// default render, bit for bit; the parts of any split put together are the default image.
#include "engine/plan.h"
#include "render_scenes.h"

#include <doctest/doctest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <set>

using namespace arbor;
using engine::IntegratorKind;

namespace {

/// Renders the tiles of one part of a scattered split of the frame, last tile first, on every
/// thread; counts what it did.
class SplitTiles final : public engine::TileSource {
public:
    SplitTiles(int part, int parts) : part_(part), parts_(parts) {}
    static int owner(int tile, int parts) { return (tile * 7 + 3) % parts; }

    void run(const engine::TileGrid& grid, engine::Image&, engine::Progress& progress,
             const std::function<void(int)>& render_tile) override {
        std::vector<int> mine;
        for (int i = grid.count() - 1; i >= 0; --i)
            if (owner(i, parts_) == part_) mine.push_back(i);
        tbb::parallel_for(0, int(mine.size()), [&](int k) {
            render_tile(mine[std::size_t(k)]);
            progress.tick();
            ++rendered;
        });
    }
    void gather(engine::RenderStats& stats) override { gathered_rays = stats.total(); }

    std::atomic<int> rendered{0};
    std::uint64_t gathered_rays = 0;

private:
    int part_, parts_;
};

}  // namespace

TEST_CASE("render: tile grid numbers the tiles row by row and clips the last row and column") {
    const engine::TileGrid g{37, 20, 16};
    CHECK(g.columns() == 3);
    CHECK(g.rows() == 2);
    CHECK(g.count() == 6);
    int x0, y0, x1, y1;
    g.bounds(5, x0, y0, x1, y1);
    CHECK((x0 == 32 && y0 == 16 && x1 == 37 && y1 == 20));
    g.bounds(1, x0, y0, x1, y1);
    CHECK((x0 == 16 && y0 == 0 && x1 == 32 && y1 == 16));
}

TEST_CASE("render: the parts of a split tile source put together equal the default render bit for bit") {
    auto scene = testing::small_scene();
    scene.mesh.append(engine::with_material(engine::make_ground(2.5f, 0.0f, 0.0f, 0.4f), testing::emitter(5.0f)));
    scene.mesh.compute_bounds();
    const accel::BruteAccel brute(scene.mesh.view());
    const engine::LightSet lights(scene);
    for (const IntegratorKind k : {IntegratorKind::direct, IntegratorKind::path}) {
        CAPTURE(engine::to_string(k));
        auto set = testing::tiny_settings(k, 37, 21, 3);
        set.layers = engine::Layers{true, true, true};
        const engine::RenderPlan plan = engine::make_plan(scene, lights, set);
        engine::RenderStats whole_stats;
        const engine::Image whole = engine::render(scene, lights, plan, brute, set, &whole_stats);
        const engine::TileGrid grid{set.width, set.height, set.tile};
        for (const int parts : {1, 2, 3}) {
            CAPTURE(parts);
            engine::Image joined(set.width, set.height, whole.names);
            std::uint64_t rays = 0;
            for (int part = 0; part < parts; ++part) {
                SplitTiles source(part, parts);
                engine::RenderStats stats;
                const engine::Image img = engine::render(scene, lights, plan, brute, set, &stats, &source);
                CHECK(source.gathered_rays == stats.total());
                rays += stats.total();
                int expected = 0;
                for (int t = 0; t < grid.count(); ++t) {
                    int x0, y0, x1, y1;
                    grid.bounds(t, x0, y0, x1, y1);
                    const bool mine = SplitTiles::owner(t, parts) == part;
                    expected += mine;
                    for (std::size_t c = 0; c < img.planes.size(); ++c)
                        for (int y = y0; y < y1; ++y)
                            for (int x = x0; x < x1; ++x) {
                                if (mine) {
                                    joined.at(int(c), x, y) = img.at(int(c), x, y);
                                } else {
                                    REQUIRE(img.at(int(c), x, y) == 0.0f);  // only its own tiles were rendered
                                }
                            }
                }
                CHECK(source.rendered == expected);
            }
            CHECK(rays == whole_stats.total());
            for (std::size_t c = 0; c < whole.planes.size(); ++c) {
                CAPTURE(whole.names[c]);
                CHECK(joined.planes[c] == whole.planes[c]);
            }
        }
    }
}
