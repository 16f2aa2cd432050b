#pragma once
/// The picture of a cost render (integrator `cost`): one or several structures' cost images side by
/// side, colour-mapped with viridis on one shared scale per quantity, labelled, with a scale bar.
///
/// Two rows, one per quantity: nodes visited per camera ray, then triangles tested per camera ray.
/// Each row holds a title line, two label lines above every panel ("NAME X Mrays/s +-E%",
/// "mean M QUANTITY/ray (max K)"), the panels, and a colour bar across the row with its numbers.
/// The scale of a row runs from 0 to a round number at or above the 99.5th percentile of that
/// quantity over all its panels' pixels (a few extreme pixels do not wash out the rest); costlier
/// pixels take the top colour and the last number reads "N+".
#include "engine/image.h"
#include "engine/rgb_image.h"

#include <span>
#include <string>
#include <vector>

namespace arbor::engine {

/// One structure's cost render.
struct CostPanel {
    std::string name;            ///< the structure, e.g. "bvh-sah"
    const Image* image = nullptr;  ///< channels nodes and tris (render with IntegratorKind::cost)
    double mrays_per_s = 0.0;    ///< its camera rays traced on the normal path
    double spread = 0.0;         ///< the accuracy of mrays_per_s, relative (0.1: +-10%; 0: not shown)
};

/// Means and maxima of a cost image's two channels.
struct CostSummary {
    double mean_nodes = 0, mean_tris = 0, max_nodes = 0, max_tris = 0;
};
CostSummary summarize_cost(const Image& cost);

/// Where everything is on a sheet of `panels` panels of w x h pixels. Every length is a multiple
/// of `scale` (1, or 2 for panels at least 480 pixels wide), the font's pixel size.
struct CostSheetLayout {
    int panels = 1, w = 1, h = 1;
    int scale = 1;
    int pad = 4, line = 9, bar = 8;  ///< margin, text line height, colour bar height
    int width = 0, height = 0;       ///< the whole sheet
    int row_height = 0;

    CostSheetLayout(int panels, int w, int h);
    int panel_x(int i) const { return pad + i * (w + pad); }
    int row_y(int row) const { return pad + row * row_height; }
    int title_y(int row) const { return row_y(row); }
    int label_y(int row, int line_index) const { return row_y(row) + (1 + line_index) * line; }
    int image_y(int row) const { return row_y(row) + 3 * line; }
    int bar_y(int row) const { return image_y(row) + h + pad; }
    int numbers_y(int row) const { return bar_y(row) + bar + 2 * scale; }
};

/// The upper end of a row's scale: the smallest of 1, 1.2, 1.6, 2, 2.4, 3, 4, 5, 6, 8 times a power
/// of ten at or above `value` (1 for value <= 0); its quarters are round numbers too.
double round_scale(double value);

/// The top of the colour scale for these values: round_scale of their 99.5th percentile.
double cost_scale_top(std::vector<float> values);

/// The sheet of `panels` (all the same size, at least one).
RgbImage cost_sheet(std::span<const CostPanel> panels);

/// The row titles and panel labels as drawn (tests read them back from the pixels).
std::string cost_row_title(int row);
std::string cost_label(const CostPanel& p, const CostSummary& s, int row, int line_index);

}  // namespace arbor::engine
