#pragma once
/// Planar float images and their outputs: OpenEXR with named channels (the only OpenEXR user in
/// the tree) and a tone-mapped 8-bit PNG preview. Both are written atomically.
#include <span>
#include <string>
#include <vector>

namespace arbor::engine {

/// A planar float image with `channels` named planes (e.g. R, G, B, Z, N.X, ...).
struct Image {
    int width = 0, height = 0;
    std::vector<std::string> names;
    std::vector<std::vector<float>> planes;

    Image() = default;
    Image(int w, int h, std::vector<std::string> channel_names);

    /// Index of a channel by name, or -1.
    int channel(const std::string& name) const;
    float& at(int c, int x, int y) { return planes[std::size_t(c)][std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    float at(int c, int x, int y) const { return planes[std::size_t(c)][std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

/// Writes every channel as 32-bit float, ZIP-compressed.
void write_exr(const std::string& path, const Image& img);
/// Reads the channels of an EXR file written by write_exr (or any float/half EXR).
Image read_exr(const std::string& path);
/// Tone-maps channels R, G, B (radiance x 2^exposure_ev, clamp, sRGB curve) into an 8-bit RGB PNG.
void write_png_preview(const std::string& path, const Image& img, float exposure_ev = 0.0f);

}  // namespace arbor::engine
