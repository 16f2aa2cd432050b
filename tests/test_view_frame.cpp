// The viewer's picture and session (view/frame.h, view/session.h), without a network: the mean of
// the passes, JPEG frames that decode to the picture, and a session driven through a recording
// Sink: frames refine one sample at a time up to the target and wait for the page's ack, a new
// camera starts over, stop() cancels and never calls the Sink again.
#include "render_scenes.h"
#include "view/frame.h"
#include "view/session.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>

using namespace arbor;

TEST_CASE("view frame: the picture is the mean of the passes, and the JPEG decodes to it") {
    engine::Image a(32, 16, {"R", "G", "B"}), b(32, 16, {"R", "G", "B"});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) a.at(c, x, y) = float(x) / 31.0f, b.at(c, x, y) = c == 0 ? 1.0f : 0.0f;
    view::Accumulator acc;
    acc.add(a);
    acc.add(b);
    CHECK(acc.samples() == 2);
    const engine::RgbImage pic = acc.picture();
    // (0 + 1) / 2 = 0.5 in red at x = 0: sRGB 188; green (31/31 + 0) / 2 = 0.5 at x = 31.
    CHECK(pic.get(0, 0)[0] == 188);
    CHECK(pic.get(31, 0)[1] == 188);
    CHECK(pic.get(0, 0)[1] == 0);
    const engine::RgbImage back = view::decode_jpeg(view::encode_jpeg(pic, 95));
    REQUIRE(back.width == 32);
    REQUIRE(back.height == 16);
    double err = 0;
    for (std::size_t i = 0; i < pic.rgb.size(); ++i) err += std::abs(int(pic.rgb[i]) - int(back.rgb[i]));
    CHECK(err / double(pic.rgb.size()) < 6.0);
    acc.reset();
    CHECK(acc.samples() == 0);
    acc.add(b);
    CHECK(acc.picture().get(0, 0)[0] == 255);
    CHECK_THROWS(view::decode_jpeg("not a jpeg"));
}

namespace {

/// Records what a session sends; acks on request.
struct Recorder final : view::Sink {
    std::mutex m;
    std::condition_variable cv;
    std::vector<nlohmann::json> frames;
    std::vector<std::string> texts;
    bool closed = false;  ///< the test's page is gone: a call now is a failure
    int calls_after_close = 0;

    bool send_text(std::string_view t) override {
        const std::lock_guard lock(m);
        if (closed) ++calls_after_close;
        texts.emplace_back(t);
        cv.notify_all();
        return true;
    }
    bool send_binary(std::string_view b) override {
        const std::lock_guard lock(m);
        if (closed) ++calls_after_close;
        const std::uint32_t n = std::uint32_t(std::uint8_t(b[0])) | std::uint32_t(std::uint8_t(b[1])) << 8 |
                                std::uint32_t(std::uint8_t(b[2])) << 16 | std::uint32_t(std::uint8_t(b[3])) << 24;
        frames.push_back(nlohmann::json::parse(b.substr(4, n)));
        CHECK(b.substr(4 + n, 2) == "\xff\xd8");
        cv.notify_all();
        return true;
    }
    /// Waits for frame number `count` (1-based), at most 30 s.
    nlohmann::json wait_frame(std::size_t count) {
        std::unique_lock lock(m);
        REQUIRE(cv.wait_for(lock, std::chrono::seconds(30), [&] { return frames.size() >= count; }));
        return frames[count - 1];
    }
};

void ack(view::Session& s, const nlohmann::json& f) { s.handle(view::AckMessage{f["frame"].get<std::uint64_t>()}); }

}  // namespace

TEST_CASE("view session: refines to the target one sample per frame, waits for acks, restarts on a camera move") {
    const engine::Scene scene = testing::small_scene();
    const engine::LightSet lights(scene);
    view::StructureCache cache(scene.mesh.view(), accel::BuildConfig{});
    view::Limits limits;
    limits.max_threads = 2;
    view::ViewSettings initial;
    initial.width = 48, initial.height = 32, initial.spp = 3, initial.threads = 2;
    Recorder rec;
    {
        view::Session session(scene, lights, cache, limits, initial, rec);
        const auto hello = nlohmann::json::parse(session.hello(7));
        CHECK(hello["client"] == 7);
        CHECK(hello["triangles"] == scene.mesh.triangle_count());
        session.start();
        for (int k = 1; k <= 3; ++k) {
            const auto f = rec.wait_frame(std::size_t(k));
            CHECK(f["frame"] == k);
            CHECK(f["samples"] == k);
            CHECK(f["width"] == 48);
            CHECK(f["mrays"].contains("primary"));
            // Without the ack, no further frame comes.
            if (k == 1) {
                std::this_thread::sleep_for(std::chrono::milliseconds(200));
                const std::lock_guard lock(rec.m);
                CHECK(rec.frames.size() == 1);
            }
            ack(session, f);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        {
            const std::lock_guard lock(rec.m);
            CHECK(rec.frames.size() == 3);  // the target is reached: idle
        }
        engine::Camera cam = scene.camera;
        cam.eye.x += 0.5f;
        session.handle(view::CameraMessage{cam});
        const auto f = rec.wait_frame(4);
        CHECK(f["samples"] == 1);
        session.handle(view::SettingsMessage{std::nullopt, engine::IntegratorKind::cost, std::nullopt, std::nullopt,
                                             std::nullopt, std::nullopt, std::nullopt});
        ack(session, f);
        const auto c = rec.wait_frame(5);
        CHECK(c["integrator"] == "cost");
        CHECK(c["cost_top"].get<double>() >= 1.0);
        session.stop();
        {
            const std::lock_guard lock(rec.m);
            rec.closed = true;
        }
        ack(session, c);  // a late message after stop: nothing happens
        CHECK(session.counters().frames == 5);
    }
    CHECK(rec.calls_after_close == 0);
    CHECK(rec.texts.size() == 2);  // "building" for bvh-sah, then for its counting build
}

TEST_CASE("view frame: the tone curve equals the PNG preview's sRGB curve on every level boundary") {
    // One pass of 256 x 1 pixels holding values just below, at and above every 8-bit step.
    engine::Image img(3 * 256, 1, {"R", "G", "B"});
    auto encode = [](float v) {
        if (!(v > 0.0f)) return 0;
        v = std::min(v, 1.0f);
        const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        return int(std::lround(s * 255.0f));
    };
    std::vector<float> values;
    for (int k = 0; k < 256; ++k) {
        const float lin = k <= 10 ? (float(k) / 255.0f) / 12.92f : std::pow((float(k) / 255.0f + 0.055f) / 1.055f, 2.4f);
        values.insert(values.end(), {std::nextafter(lin, 0.0f), lin, std::nextafter(lin, 2.0f)});
    }
    for (int x = 0; x < 3 * 256; ++x) img.at(0, x, 0) = values[std::size_t(x)];
    view::Accumulator acc;
    acc.add(img);
    const engine::RgbImage pic = acc.picture();
    int off = 0;
    for (int x = 0; x < 3 * 256; ++x) off += std::abs(int(pic.get(x, 0)[0]) - encode(values[std::size_t(x)])) > 0;
    CHECK(off == 0);
}
