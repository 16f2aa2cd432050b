#pragma once
/// A 5 x 7 pixel font of printable ASCII, drawn for arbor (no font file, no library), for the
/// numbers and names on the cost images. Text is drawn at an integer scale, left to right, one
/// glyph every 6 font pixels.
#include "engine/rgb_image.h"

#include <climits>
#include <string_view>

namespace arbor::engine {

inline constexpr int glyph_width = 5, glyph_height = 7, glyph_advance = 6;

/// Whether font pixel (x, y) of c's glyph is set (y = 0 at the top; characters outside printable
/// ASCII draw as '?').
bool glyph_pixel(char c, int x, int y);
/// Width in image pixels of `text` drawn at `scale` (no trailing gap).
int text_width(std::string_view text, int scale);
/// Draws `text` with its top-left corner at (x, y), clipped to the image and to columns below
/// clip_x1; returns the x where the next glyph would start.
int draw_text(RgbImage& img, int x, int y, std::string_view text, int scale, Rgb8 colour, int clip_x1 = INT_MAX);

}  // namespace arbor::engine
