#include "engine/image.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace arbor::engine {

Image::Image(int w, int h, std::vector<std::string> channel_names)
    : width(w), height(h), names(std::move(channel_names)) {
    planes.assign(names.size(), std::vector<float>(std::size_t(w) * std::size_t(h), 0.0f));
}

int Image::channel(const std::string& name) const {
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return int(i);
    return -1;
}

void write_exr(const std::string& path, const Image& img) {
    AtomicFile out(path);
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < img.names.size(); ++c) {
            header.channels().insert(img.names[c], Imf::Channel(Imf::FLOAT));
            fb.insert(img.names[c], Imf::Slice(Imf::FLOAT, (char*)img.planes[c].data(), sizeof(float),
                                               sizeof(float) * std::size_t(img.width)));
        }
        Imf::OutputFile file(out.temp_path().c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(img.height);
    } catch (const std::exception& e) {
        throw InputError(path, 0, std::string("cannot write EXR: ") + e.what());
    }
    out.commit();
}

Image read_exr(const std::string& path) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        std::vector<std::string> names;
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
            names.emplace_back(it.name());
        Image img(w, h, names);
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < names.size(); ++c) {
            char* base = (char*)(img.planes[c].data() - dw.min.x - std::ptrdiff_t(dw.min.y) * w);
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(w)));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return img;
    } catch (const std::exception& e) {
        throw InputError(path, 0, std::string("cannot read EXR: ") + e.what());
    }
}

namespace {
std::uint8_t to_srgb8(float v) {
    if (!(v > 0.0f)) return 0;  // also maps NaN to black
    v = std::min(v, 1.0f);
    const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return std::uint8_t(std::lround(s * 255.0f));
}
}  // namespace

void write_png_preview(const std::string& path, const Image& img, float exposure_ev) {
    const float gain = std::exp2(exposure_ev);
    const int r = img.channel("R"), g = img.channel("G"), b = img.channel("B");
    if (r < 0 || g < 0 || b < 0) throw InputError(path, 0, "image has no R, G, B channels");
    std::vector<std::uint8_t> rgb(std::size_t(img.width) * std::size_t(img.height) * 3);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::size_t i = (std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 3;
            rgb[i + 0] = to_srgb8(gain * img.at(r, x, y));
            rgb[i + 1] = to_srgb8(gain * img.at(g, x, y));
            rgb[i + 2] = to_srgb8(gain * img.at(b, x, y));
        }
    AtomicFile out(path);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(img.width);
    image.height = png_uint_32(img.height);
    image.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&image, out.temp_path().c_str(), 0, rgb.data(), 0, nullptr))
        throw InputError(path, 0, std::string("cannot write PNG: ") + image.message);
    out.commit();
}

}  // namespace arbor::engine
