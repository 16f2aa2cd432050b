// The cost picture: its size for given panels, the labels read back from its pixels glyph by glyph,
// one colour scale shared by the panels, the scale's round numbers; the colour map's lightness
// rises steadily (what makes it perceptual) and the font's glyphs are all different (what makes
// the read-back unambiguous).
#include "engine/bitmap_font.h"
#include "engine/colormap.h"
#include "engine/cost_sheet.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using engine::RgbImage;

namespace {

/// The text at (x, y) drawn at `scale` in at most `cells` glyph cells left of x_end: each cell
/// matched against every glyph (set pixels must be `ink`, the others not); '\0' where nothing
/// matches. Trailing spaces are dropped.
std::string read_text(const RgbImage& img, int x, int y, int scale, int cells, engine::Rgb8 ink, int x_end = 1 << 30) {
    std::string out;
    for (int i = 0; i < cells; ++i) {
        const int cx = x + i * engine::glyph_advance * scale;
        if (cx + engine::glyph_width * scale > x_end) break;
        char found = '\0';
        for (int c = 32; c < 127 && !found; ++c) {
            bool same = true;
            for (int gy = 0; gy < engine::glyph_height && same; ++gy)
                for (int gx = 0; gx < engine::glyph_width && same; ++gx) {
                    const int px = cx + gx * scale, py = y + gy * scale;
                    if (px >= img.width) return out;
                    same = (img.get(px, py) == ink) == engine::glyph_pixel(char(c), gx, gy);
                }
            if (same) found = char(c);
        }
        out += found;
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

constexpr engine::Rgb8 ink{235, 235, 235};

/// A cost image whose nodes are x + y and tris 2x, scaled by `k`.
engine::Image ramp(int w, int h, float k) {
    engine::Image img(w, h, {"nodes", "tris"});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(0, x, y) = k * float(x + y), img.at(1, x, y) = k * float(2 * x);
    return img;
}

/// CIE L* of an sRGB colour.
double lightness(engine::Rgb8 c) {
    auto lin = [](double v) { v /= 255.0; return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
    const double y = 0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2]);
    return y > 216.0 / 24389.0 ? 116.0 * std::cbrt(y) - 16.0 : y * 24389.0 / 27.0;
}

}  // namespace

TEST_CASE("cost sheet: the size of three panels side by side, at both text scales") {
    const engine::CostSheetLayout small(3, 64, 48);
    CHECK(small.scale == 1);
    CHECK(small.width == 3 * 64 + 4 * 4);
    CHECK(small.row_height == 3 * 9 + 48 + 4 + 8 + 2 + 9 + 4);
    CHECK(small.height == 4 + 2 * 102);
    const engine::CostSheetLayout big(4, 640, 480);
    CHECK(big.scale == 2);
    CHECK(big.width == 4 * 640 + 5 * 8);
    CHECK(big.height == 8 + 2 * (3 * 18 + 480 + 8 + 16 + 4 + 18 + 8));

    const engine::Image a = ramp(64, 48, 1.0f), b = ramp(64, 48, 2.0f), c = ramp(64, 48, 0.5f);
    const engine::CostPanel panels[] = {{"bvh-sah", &a, 31.25, 0.1}, {"kdtree", &b, 4.5, 0.0}, {"lbvh", &c, 120, 0.25}};
    const RgbImage sheet = engine::cost_sheet(panels);
    CHECK(sheet.width == small.width);
    CHECK(sheet.height == small.height);
}

TEST_CASE("cost sheet: the titles and every panel's labels read back from the pixels") {
    const engine::Image a = ramp(160, 40, 1.0f), b = ramp(160, 40, 2.0f);
    const engine::CostPanel panels[] = {{"bvh-sah", &a, 31.25, 0.1}, {"kdtree", &b, 4.5, 0.0}};
    const RgbImage sheet = engine::cost_sheet(panels);
    const engine::CostSheetLayout L(2, 160, 40);
    CHECK(read_text(sheet, L.pad, L.title_y(0), 1, 40, ink) == "nodes visited per camera ray");
    CHECK(read_text(sheet, L.pad, L.title_y(1), 1, 40, ink) == "triangles tested per camera ray");
    // a: nodes x + y over 160 x 40 has mean 79.5 + 19.5 = 99, max 159 + 39 = 198; tris 2x: mean 159, max 318.
    // Each label within its panel's 160 columns (26 glyphs).
    const auto label = [&](int panel, int row, int line) {
        return read_text(sheet, L.panel_x(panel), L.label_y(row, line), 1, 40, ink, L.panel_x(panel) + 160);
    };
    CHECK(label(0, 0, 0) == "bvh-sah 31.2 Mrays/s +-10%");
    CHECK(label(0, 0, 1) == "mean 99 nodes/ray, max 198");
    CHECK(label(0, 1, 0) == "bvh-sah 31.2 Mrays/s +-10%");
    CHECK(label(0, 1, 1) == "mean 159 tris/ray, max 318");
    CHECK(label(1, 0, 0) == "kdtree 4.5 Mrays/s");
    CHECK(label(1, 1, 1) == "mean 318 tris/ray, max 636");
    // The shared scale of the nodes row: the 99.5th percentile of both panels' 12800 pixels is the
    // 64th largest, b's 2 (x + y) at x + y = 188 (b has k + 1 pixels at x + y = 198 - k): 376,
    // rounded up to 400; no pixel is above it.
    const int x1 = L.panel_x(1) + 160;
    CHECK(read_text(sheet, L.panel_x(0), L.numbers_y(0), 1, 4, ink) == "0");
    CHECK(read_text(sheet, x1 - engine::text_width("400", 1), L.numbers_y(0), 1, 4, ink) == "400");
    const int mid = L.panel_x(0) + (x1 - 1 - L.panel_x(0)) / 2;
    CHECK(read_text(sheet, mid - engine::text_width("200", 1) / 2, L.numbers_y(0), 1, 3, ink) == "200");
}

TEST_CASE("cost sheet: the panels share one colour scale per row") {
    engine::Image a(8, 8, {"nodes", "tris"}), b(8, 8, {"nodes", "tris"});
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) a.at(0, x, y) = 10.0f, b.at(0, x, y) = x < 4 ? 10.0f : 40.0f;
    const engine::CostPanel panels[] = {{"a", &a, 1, 0}, {"b", &b, 1, 0}};
    const RgbImage sheet = engine::cost_sheet(panels);
    const engine::CostSheetLayout L(2, 8, 8);
    const auto px = [&](int panel, int x) { return sheet.get(L.panel_x(panel) + x, L.image_y(0)); };
    CHECK(px(0, 0) == px(1, 0));  // the same cost, the same colour in both panels
    CHECK(px(1, 7) == engine::viridis(1.0f));  // 40 is the top of the scale (round_scale(40) = 40)
    CHECK(px(0, 0) == engine::viridis(0.25f));
    CHECK(px(1, 0) != px(1, 7));
}

TEST_CASE("cost sheet: scales end on round numbers whose quarters are round") {
    CHECK(engine::round_scale(0) == 1);
    CHECK(engine::round_scale(1) == 1);
    CHECK(engine::round_scale(1.01) == doctest::Approx(1.2));
    CHECK(engine::round_scale(57) == doctest::Approx(60));
    CHECK(engine::round_scale(81) == doctest::Approx(100));
    CHECK(engine::round_scale(0.013) == doctest::Approx(0.016));
    CHECK(engine::round_scale(2500) == doctest::Approx(3000));
}

TEST_CASE("colormap: viridis ends where matplotlib's does and its lightness rises steadily") {
    CHECK(engine::viridis(0.0f) == engine::Rgb8{68, 1, 84});
    CHECK(engine::viridis(1.0f) == engine::Rgb8{253, 231, 37});
    CHECK(engine::viridis(-3.0f) == engine::viridis(0.0f));
    CHECK(engine::viridis(std::nanf("")) == engine::viridis(0.0f));
    CHECK(engine::viridis(7.0f) == engine::viridis(1.0f));
    // matplotlib's entry 128 of 255: (33, 145, 140).
    const auto mid = engine::viridis(128.0f / 255.0f);
    CHECK(std::abs(int(mid[0]) - 33) <= 2);
    CHECK(std::abs(int(mid[1]) - 145) <= 2);
    CHECK(std::abs(int(mid[2]) - 140) <= 2);
    double last = -1;
    for (int i = 0; i <= 64; ++i) {
        const double l = lightness(engine::viridis(float(i) / 64.0f));
        CHECK(l > last);
        if (i > 0) CHECK(l - last < 3.0);  // steady: about 1.3 L* per 1/64
        last = l;
    }
}

TEST_CASE("bitmap font: the glyphs of printable ASCII are all different and the space is empty") {
    auto bits = [](char c) {
        std::uint64_t b = 0;
        for (int y = 0; y < engine::glyph_height; ++y)
            for (int x = 0; x < engine::glyph_width; ++x) b = b << 1 | std::uint64_t(engine::glyph_pixel(c, x, y));
        return b;
    };
    CHECK(bits(' ') == 0);
    for (int a = 32; a < 127; ++a)
        for (int b = a + 1; b < 127; ++b) {
            CAPTURE(char(a));
            CAPTURE(char(b));
            CHECK(bits(char(a)) != bits(char(b)));
        }
    CHECK(bits('\n') == bits('?'));
    CHECK(engine::text_width("ab", 2) == (2 * 6 - 1) * 2);
}
