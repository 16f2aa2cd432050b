#pragma once
/// The viewer's picture: the passes of a progressive render summed (one sample per pixel each),
/// shown as their mean, made 8-bit and sent as JPEG (libturbojpeg).
#include "engine/image.h"
#include "engine/rgb_image.h"

#include <string>

namespace arbor::view {

class Accumulator {
public:
    /// Starts over (a new camera or settings): no sample yet.
    void reset();
    /// Adds one pass (same channels and size as the previous ones since reset).
    void add(const engine::Image& pass);
    int samples() const { return samples_; }
    const engine::Image& sums() const { return sums_; }

    /// The mean so far as a picture: R, G, B tone-mapped as the PNG preview is (clamped, sRGB
    /// curve); or, for a cost image, channel `cost_channel` colour-mapped with viridis on [0, top]
    /// with top = engine::cost_scale_top of its values, returned in `cost_top`.
    engine::RgbImage picture(const std::string& cost_channel = {}, double* cost_top = nullptr) const;

private:
    engine::Image sums_;
    int samples_ = 0;
};

/// `img` as a baseline JPEG of `quality` (1..100, 4:2:0); std::runtime_error if libturbojpeg fails.
std::string encode_jpeg(const engine::RgbImage& img, int quality = 85);
/// Decodes a JPEG to RGB (tests); std::runtime_error on bad data.
engine::RgbImage decode_jpeg(const std::string& jpeg);

}  // namespace arbor::view
