#pragma once
/// An 8-bit RGB image (interleaved, rows top to bottom) for pictures made to be looked at: the
/// cost sheets, the viewer's frames. Written as PNG atomically.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace arbor::engine {

using Rgb8 = std::array<std::uint8_t, 3>;

struct RgbImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes

    RgbImage() = default;
    RgbImage(int w, int h, Rgb8 fill = {0, 0, 0});

    Rgb8 get(int x, int y) const {
        const std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, Rgb8 c) {
        std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
        p[0] = c[0], p[1] = c[1], p[2] = c[2];
    }
    /// Fills [x0, x1) x [y0, y1), clipped to the image.
    void fill(int x0, int y0, int x1, int y1, Rgb8 c);
};

/// Writes `img` as an 8-bit RGB PNG through a temporary file (InputError naming `path` on failure).
void write_png(const std::string& path, const RgbImage& img);
/// Reads an 8-bit RGB or RGBA PNG (alpha dropped); InputError naming `path` on failure.
RgbImage read_png(const std::string& path);

}  // namespace arbor::engine
