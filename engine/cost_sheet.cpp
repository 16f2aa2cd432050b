#include "engine/cost_sheet.h"

#include "engine/bitmap_font.h"
#include "engine/colormap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace arbor::engine {

namespace {

constexpr Rgb8 background{24, 24, 28}, ink{235, 235, 235}, tick_ink{160, 160, 160};
constexpr const char* quantity[2] = {"nodes", "tris"};

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

}  // namespace

double cost_scale_top(std::vector<float> v) {
    if (v.empty()) return round_scale(0.0);
    const std::size_t k = std::min(v.size() - 1, std::size_t(0.995 * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return round_scale(v[k]);
}

CostSummary summarize_cost(const Image& cost) {
    const int n = cost.channel("nodes"), t = cost.channel("tris");
    if (n < 0 || t < 0) throw std::invalid_argument("summarize_cost: the image has no nodes and tris channels");
    CostSummary s;
    const std::size_t count = cost.planes[std::size_t(n)].size();
    for (std::size_t i = 0; i < count; ++i) {
        const double a = cost.planes[std::size_t(n)][i], b = cost.planes[std::size_t(t)][i];
        s.mean_nodes += a, s.mean_tris += b;
        s.max_nodes = std::max(s.max_nodes, a), s.max_tris = std::max(s.max_tris, b);
    }
    if (count) s.mean_nodes /= double(count), s.mean_tris /= double(count);
    return s;
}

CostSheetLayout::CostSheetLayout(int n, int pw, int ph) : panels(n), w(pw), h(ph) {
    scale = w >= 480 ? 2 : 1;
    pad = 4 * scale, line = 9 * scale, bar = 8 * scale;
    width = n * w + (n + 1) * pad;
    row_height = 3 * line + h + pad + bar + 2 * scale + line + pad;
    height = pad + 2 * row_height;
}

double round_scale(double value) {
    if (!(value > 0.0)) return 1.0;
    static constexpr double steps[] = {1, 1.2, 1.6, 2, 2.4, 3, 4, 5, 6, 8, 10};
    double decade = std::pow(10.0, std::floor(std::log10(value)));
    for (;;) {
        for (double s : steps)
            if (s * decade >= value * (1.0 - 1e-12)) return s * decade;
        decade *= 10.0;
    }
}

std::string cost_row_title(int row) {
    return row == 0 ? "nodes visited per camera ray" : "triangles tested per camera ray";
}

std::string cost_label(const CostPanel& p, const CostSummary& s, int row, int line_index) {
    if (line_index == 0)
        return p.name + " " + format("%.3g", p.mrays_per_s) + " Mrays/s" +
               (p.spread > 0 ? " +-" + format("%.0f", 100.0 * p.spread) + "%" : "");
    const double mean = row == 0 ? s.mean_nodes : s.mean_tris, max = row == 0 ? s.max_nodes : s.max_tris;
    return "mean " + format("%.3g", mean) + " " + quantity[row] + "/ray, max " + format("%.3g", max);
}

RgbImage cost_sheet(std::span<const CostPanel> panels) {
    if (panels.empty()) throw std::invalid_argument("cost_sheet: no panel");
    const int w = panels[0].image->width, h = panels[0].image->height;
    for (const CostPanel& p : panels)
        if (p.image->width != w || p.image->height != h) throw std::invalid_argument("cost_sheet: panels differ in size");
    const CostSheetLayout L(int(panels.size()), w, h);
    RgbImage img(L.width, L.height, background);
    std::vector<CostSummary> summaries;
    for (const CostPanel& p : panels) summaries.push_back(summarize_cost(*p.image));
    for (int row = 0; row < 2; ++row) {
        const int c = panels[0].image->channel(quantity[row]);
        std::vector<float> values;
        for (const CostPanel& p : panels) values.insert(values.end(), p.image->planes[std::size_t(c)].begin(), p.image->planes[std::size_t(c)].end());
        const double top = cost_scale_top(std::move(values));
        draw_text(img, L.pad, L.title_y(row), cost_row_title(row), L.scale, ink);
        bool saturated = false;
        for (std::size_t i = 0; i < panels.size(); ++i) {
            const int x0 = L.panel_x(int(i)), clip = x0 + w;
            for (int k = 0; k < 2; ++k)
                draw_text(img, x0, L.label_y(row, k), cost_label(panels[i], summaries[i], row, k), L.scale, ink, clip);
            const Image& src = *panels[i].image;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float v = src.at(c, x, y);
                    saturated |= v > top;
                    img.set(x0 + x, L.image_y(row) + y, viridis(float(v / top)));
                }
        }
        // The colour bar across the row, its quarter ticks and their numbers.
        const int bx0 = L.panel_x(0), bx1 = L.panel_x(L.panels - 1) + w;
        for (int x = bx0; x < bx1; ++x) {
            const Rgb8 col = viridis(bx1 - bx0 > 1 ? float(x - bx0) / float(bx1 - bx0 - 1) : 0.0f);
            img.fill(x, L.bar_y(row), x + 1, L.bar_y(row) + L.bar, col);
        }
        for (int q = 0; q <= 4; ++q) {
            const int tx = bx0 + (bx1 - 1 - bx0) * q / 4;
            img.fill(tx, L.bar_y(row) + L.bar, tx + L.scale, L.bar_y(row) + L.bar + 2 * L.scale, tick_ink);
            std::string label = format("%g", top * q / 4);
            if (q == 4 && saturated) label += "+";
            const int tw = text_width(label, L.scale);
            const int lx = q == 0 ? bx0 : q == 4 ? bx1 - tw : tx - tw / 2;
            draw_text(img, lx, L.numbers_y(row), label, L.scale, ink);
        }
    }
    return img;
}

}  // namespace arbor::engine
