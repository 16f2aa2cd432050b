#include "engine/rgb_image.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <png.h>

#include <algorithm>

namespace arbor::engine {

RgbImage::RgbImage(int w, int h, Rgb8 c) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3) {
    fill(0, 0, w, h, c);
}

void RgbImage::fill(int x0, int y0, int x1, int y1, Rgb8 c) {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, width), y1 = std::min(y1, height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) set(x, y, c);
}

void write_png(const std::string& path, const RgbImage& img) {
    AtomicFile out(path);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(img.width);
    image.height = png_uint_32(img.height);
    image.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&image, out.temp_path().c_str(), 0, img.rgb.data(), 0, nullptr))
        throw InputError(path, 0, std::string("cannot write PNG: ") + image.message);
    out.commit();
}

RgbImage read_png(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str()))
        throw InputError(path, 0, std::string("cannot read PNG: ") + image.message);
    image.format = PNG_FORMAT_RGB;
    RgbImage img(int(image.width), int(image.height));
    if (!png_image_finish_read(&image, nullptr, img.rgb.data(), 0, nullptr))
        throw InputError(path, 0, std::string("cannot read PNG: ") + image.message);
    return img;
}

}  // namespace arbor::engine
