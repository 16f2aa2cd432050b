#include "view/frame.h"

#include "engine/colormap.h"
#include "engine/cost_sheet.h"

#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace arbor::view {

namespace {

/// The sRGB curve to 8 bits as the PNG preview computes it, without a pow per channel (which cost
/// 20-30 ms per 640 x 480 frame): the 255 linear values where the output level steps up are worked
/// out once (bisection on the exact curve); a table over [0, 1] in 4096 buckets gives the level at
/// the start of v's bucket, and the steps inside the bucket (at most one; none for most buckets)
/// are checked one by one, so the result is exact.
class Srgb8 {
public:
    Srgb8() {
        for (int k = 1; k < 256; ++k) {
            float lo = 0.0f, hi = 1.0f;  // the smallest v with encode(v) >= k
            for (int i = 0; i < 40; ++i) {
                const float mid = 0.5f * (lo + hi);
                (encode(mid) >= k ? hi : lo) = mid;
            }
            step_[k - 1] = hi;
        }
        step_[255] = 2.0f;  // no level above 255
        for (int b = 0; b < buckets; ++b)
            start_[b] = std::uint8_t(std::upper_bound(step_, step_ + 255, float(b) / float(buckets)) - step_);
    }
    std::uint8_t operator()(float v) const {
        if (!(v > 0.0f)) return 0;  // also NaN
        if (v >= 1.0f) return 255;
        int level = start_[int(v * float(buckets))];
        while (v >= step_[level]) ++level;
        return std::uint8_t(level);
    }
    static int encode(float v) {
        v = std::min(v, 1.0f);
        const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        return int(std::lround(s * 255.0f));
    }

private:
    static constexpr int buckets = 4096;
    float step_[256];  ///< step_[k]: the smallest value shown as level k + 1
    std::uint8_t start_[buckets];
};

const Srgb8 srgb8;

struct TjFree {
    void operator()(void* h) const { tjDestroy(h); }
};

}  // namespace

void Accumulator::reset() {
    samples_ = 0;
}

void Accumulator::add(const engine::Image& pass) {
    if (samples_ == 0 || sums_.width != pass.width || sums_.height != pass.height || sums_.names != pass.names) {
        sums_ = pass;
        samples_ = 1;
        return;
    }
    for (std::size_t c = 0; c < sums_.planes.size(); ++c)
        for (std::size_t i = 0; i < sums_.planes[c].size(); ++i) sums_.planes[c][i] += pass.planes[c][i];
    ++samples_;
}

engine::RgbImage Accumulator::picture(const std::string& cost_channel, double* cost_top) const {
    engine::RgbImage out(sums_.width, sums_.height);
    if (samples_ == 0) return out;
    const float inv = 1.0f / float(samples_);
    if (!cost_channel.empty()) {
        const int c = sums_.channel(cost_channel);
        if (c < 0) throw std::invalid_argument("Accumulator::picture: no channel " + cost_channel);
        std::vector<float> mean(sums_.planes[std::size_t(c)]);
        for (float& v : mean) v *= inv;
        const double top = engine::cost_scale_top(mean);
        if (cost_top) *cost_top = top;
        for (int y = 0; y < sums_.height; ++y)
            for (int x = 0; x < sums_.width; ++x)
                out.set(x, y, engine::viridis(float(mean[std::size_t(y) * std::size_t(sums_.width) + std::size_t(x)] / top)));
        return out;
    }
    const int r = sums_.channel("R"), g = sums_.channel("G"), b = sums_.channel("B");
    if (r < 0 || g < 0 || b < 0) throw std::invalid_argument("Accumulator::picture: no R, G, B channels");
    for (int y = 0; y < sums_.height; ++y)
        for (int x = 0; x < sums_.width; ++x)
            out.set(x, y, {srgb8(sums_.at(r, x, y) * inv), srgb8(sums_.at(g, x, y) * inv), srgb8(sums_.at(b, x, y) * inv)});
    return out;
}

std::string encode_jpeg(const engine::RgbImage& img, int quality) {
    const std::unique_ptr<void, TjFree> tj(tjInitCompress());
    if (!tj) throw std::runtime_error("libturbojpeg: cannot start a compressor");
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    if (tjCompress2(tj.get(), img.rgb.data(), img.width, 0, img.height, TJPF_RGB, &buf, &size, TJSAMP_420, quality,
                    TJFLAG_FASTDCT) != 0) {
        tjFree(buf);
        throw std::runtime_error(std::string("libturbojpeg: ") + tjGetErrorStr2(tj.get()));
    }
    std::string out(reinterpret_cast<const char*>(buf), size);
    tjFree(buf);
    return out;
}

engine::RgbImage decode_jpeg(const std::string& jpeg) {
    const std::unique_ptr<void, TjFree> tj(tjInitDecompress());
    if (!tj) throw std::runtime_error("libturbojpeg: cannot start a decompressor");
    int w = 0, h = 0, sub = 0, space = 0;
    auto* data = reinterpret_cast<const unsigned char*>(jpeg.data());
    if (tjDecompressHeader3(tj.get(), data, jpeg.size(), &w, &h, &sub, &space) != 0)
        throw std::runtime_error(std::string("libturbojpeg: ") + tjGetErrorStr2(tj.get()));
    engine::RgbImage img(w, h);
    if (tjDecompress2(tj.get(), data, jpeg.size(), img.rgb.data(), w, 0, h, TJPF_RGB, 0) != 0)
        throw std::runtime_error(std::string("libturbojpeg: ") + tjGetErrorStr2(tj.get()));
    return img;
}

}  // namespace arbor::view
