// Outputs of the renderer: image error metrics, the progress bar text, the run summary, and the
// EXR layers surviving a write/read round trip.
#include "engine/error.h"
#include "engine/image_metrics.h"
#include "engine/progress.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <filesystem>

using namespace arbor;

TEST_CASE("image metrics: rmse and relative mse of known differences") {
    engine::Image a(2, 1, {"R", "G", "B"}), b(2, 1, {"B", "G", "R"});
    for (auto& p : a.planes) p = {1.0f, 0.0f};
    for (auto& p : b.planes) p = {1.0f, 0.0f};
    CHECK(engine::compare_rgb(a, b).rmse == 0.0);
    a.planes[0][1] = 0.3f;  // R of pixel 1: reference 0, error 0.3 on one value of six
    const auto e = engine::compare_rgb(a, b);
    CHECK(e.rmse == doctest::Approx(std::sqrt(0.09 / 6)));
    CHECK(e.rel_mse == doctest::Approx(0.09 / 0.01 / 6));
    CHECK(e.mean == doctest::Approx((3.0 + 0.3) / 6));
    engine::Image small(1, 1, {"R", "G", "B"});
    CHECK_THROWS_AS(engine::compare_rgb(small, b), engine::InputError);
    engine::Image grey(2, 1, {"Y"});
    CHECK_THROWS_AS(engine::compare_rgb(a, grey), engine::InputError);
}

TEST_CASE("progress bar: fraction, elapsed and time left") {
    CHECK(engine::Progress::bar("r", 1, 4, 2.0, 8) == "r [##      ]  25%  2.0 s, ~6.0 s left");
    CHECK(engine::Progress::bar("r", 4, 4, 3.0, 4) == "r [####] 100%  3.0 s");
    CHECK(engine::Progress::bar("r", 0, 4, 0.0, 4) == "r [    ]   0%  0.0 s");
}

TEST_CASE("render stats: summary names every kind traced, and only those") {
    engine::RenderStats st;
    st.seconds = 2.0;
    st.threads = 2;
    st.rays[std::size_t(engine::RenderRayKind::primary)] = 4000000;
    st.trace_seconds[std::size_t(engine::RenderRayKind::primary)] = 2.0;
    const std::string s = st.summary();
    CHECK(s.find("2 Mrays/s overall") != std::string::npos);
    CHECK(s.find("primary 4e+06 at 4 Mrays/s") != std::string::npos);
    CHECK(s.find("shadow") == std::string::npos);
}

TEST_CASE("render: EXR layers round-trip with their names") {
    auto set = testing::tiny_settings(engine::IntegratorKind::primary, 12, 9, 1);
    const auto img = testing::render_brute(testing::small_scene(), set);
    const auto path = std::filesystem::temp_directory_path() / "arbor_test_layers.exr";
    engine::write_exr(path.string(), img);
    const auto back = engine::read_exr(path.string());
    std::filesystem::remove(path);
    REQUIRE(back.names.size() == img.names.size());
    for (std::size_t c = 0; c < img.names.size(); ++c) {
        const int k = back.channel(img.names[c]);
        REQUIRE(k >= 0);
        CHECK(back.planes[std::size_t(k)] == img.planes[c]);
    }
}
