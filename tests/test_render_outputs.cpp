// Outputs of the renderer: image error metrics, the progress bar text, the run summary, and the
// EXR layers surviving a write/read round trip.
#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/image_metrics.h"
#include "engine/image_output.h"
#include "engine/progress.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cstring>
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

TEST_CASE("render outputs: the format follows the extension and PFM round-trips R, G, B bit for bit") {
    CHECK(engine::output_format("a/b.exr") == engine::OutputFormat::exr);
    CHECK(engine::output_format("b.PNG") == engine::OutputFormat::png);
    CHECK(engine::output_format("b.pfm") == engine::OutputFormat::pfm);
    CHECK_FALSE(engine::output_format("b.jpg"));
    CHECK_FALSE(engine::output_format("exr"));
    const auto dir = std::filesystem::temp_directory_path();
    CHECK(engine::output_problem((dir / "x.exr").string()).empty());
    CHECK(engine::output_problem("x.jpg").find("'x.jpg': unknown output format .jpg") == 0);
    CHECK(engine::output_problem((dir / "no-such-folder/x.png").string()).find("does not exist") != std::string::npos);
    CHECK(engine::output_problem(dir.string() + "/.png").find("is a folder") == std::string::npos);

    auto set = testing::tiny_settings(engine::IntegratorKind::primary, 7, 5, 1);
    const auto img = testing::render_brute(testing::small_scene(), set);
    const auto path = (dir / "arbor_test_rgb.pfm").string();
    CHECK(engine::write_outputs(path, img) == std::vector<std::string>{path});
    const auto back = engine::read_pfm(path);
    std::filesystem::remove(path);
    REQUIRE(back.width == 7);
    REQUIRE(back.height == 5);
    for (int c = 0; c < 3; ++c) CHECK(back.planes[std::size_t(c)] == img.planes[std::size_t(c)]);
    // A top-left bright pixel stays top-left (PFM stores the bottom row first).
    engine::Image marker(2, 2, {"R", "G", "B"});
    marker.at(0, 0, 0) = 5.0f;
    engine::write_pfm(path, marker);
    CHECK(engine::read_pfm(path).at(0, 0, 0) == 5.0f);
    const std::string bytes = engine::read_file(path);
    const std::string header = "PF\n2 2\n-1.0\n";
    REQUIRE(bytes.size() == header.size() + 48);
    CHECK(bytes.compare(0, header.size(), header) == 0);
    float first_of_second_row = 0.0f;  // the file's second row is the image's top row
    std::memcpy(&first_of_second_row, bytes.data() + header.size() + 24, 4);
    CHECK(first_of_second_row == 5.0f);
    std::filesystem::remove(path);
}
