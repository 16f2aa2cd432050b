#include "engine/image_metrics.h"

#include "engine/error.h"

#include <cmath>

namespace arbor::engine {

namespace {
void rgb_channels(const Image& img, const std::string& name, int (&c)[3]) {
    const char* names[3] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
        c[k] = img.channel(names[k]);
        if (c[k] < 0) throw InputError(name + ": no channel " + names[k]);
    }
}
}  // namespace

ImageError compare_rgb(const Image& img, const Image& ref, const std::string& ref_name) {
    if (img.width != ref.width || img.height != ref.height)
        throw InputError(ref_name + ": is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                         ", the image is " + std::to_string(img.width) + "x" + std::to_string(img.height));
    int a[3], b[3];
    rgb_channels(img, "image", a);
    rgb_channels(ref, ref_name, b);
    double se = 0.0, rel = 0.0, sum = 0.0;
    const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
    for (int k = 0; k < 3; ++k) {
        const auto& x = img.planes[std::size_t(a[k])];
        const auto& r = ref.planes[std::size_t(b[k])];
        for (std::size_t i = 0; i < n; ++i) {
            const double d = double(x[i]) - double(r[i]);
            se += d * d;
            rel += d * d / (double(r[i]) * double(r[i]) + 0.01);
            sum += x[i];
        }
    }
    const double count = double(3 * n);
    ImageError e;
    e.rmse = n ? std::sqrt(se / count) : 0.0;
    e.rel_mse = n ? rel / count : 0.0;
    e.mean = n ? sum / count : 0.0;
    return e;
}

double mean_rgb(const Image& img) {
    int a[3];
    rgb_channels(img, "image", a);
    double sum = 0.0;
    for (int k = 0; k < 3; ++k)
        for (float v : img.planes[std::size_t(a[k])]) sum += v;
    const double count = 3.0 * double(img.width) * double(img.height);
    return count > 0 ? sum / count : 0.0;
}

}  // namespace arbor::engine
