#include "engine/texture.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <stb_image.h>

#include <array>
#include <cmath>
#include <memory>

namespace arbor::engine {

namespace {

const std::array<float, 256>& srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[std::size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}

/// Texel index along an axis of `n` texels for a coordinate in texel units, repeating.
int wrap(long long i, int n) {
    const long long m = i % n;
    return int(m < 0 ? m + n : m);
}

}  // namespace

float srgb_to_linear(std::uint8_t code) { return srgb_table()[code]; }

Vec3f Texture::sample(float u, float v) const {
    if (width <= 0 || height <= 0) return Vec3f{1.0f};
    if (!std::isfinite(u) || !std::isfinite(v)) u = v = 0.0f;
    // Keep only the fraction (repeat), so that huge coordinates neither overflow nor lose texels.
    u -= std::floor(u);
    v -= std::floor(v);
    const float fx = u * float(width) - 0.5f, fy = (1.0f - v) * float(height) - 0.5f;  // row 0 is the top
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float ax = fx - x0f, ay = fy - y0f;
    const int x0 = wrap((long long)x0f, width), x1 = wrap((long long)x0f + 1, width);
    const int y0 = wrap((long long)y0f, height), y1 = wrap((long long)y0f + 1, height);
    const auto& lut = srgb_table();
    auto texel = [&](int x, int y) {
        const std::uint8_t* p = &texels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
        return Vec3f{lut[p[0]], lut[p[1]], lut[p[2]]};
    };
    const Vec3f top = texel(x0, y0) * (1.0f - ax) + texel(x1, y0) * ax;
    const Vec3f bottom = texel(x0, y1) * (1.0f - ax) + texel(x1, y1) * ax;
    return top * (1.0f - ay) + bottom * ay;
}

Texture decode_texture(std::span<const unsigned char> bytes, const std::string& name) {
    if (bytes.empty() || bytes.size() > std::size_t(INT32_MAX)) throw InputError(name, 0, "empty or too large an image");
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &channels))
        throw InputError(name, 0, std::string("cannot decode the image (") + stbi_failure_reason() + ")");
    if (w < 1 || h < 1 || w > max_texture_side || h > max_texture_side)
        throw InputError(name, 0, "image is " + std::to_string(w) + "x" + std::to_string(h) + ", more than " +
                                      std::to_string(max_texture_side) + " texels on a side");
    const std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &channels, 3), stbi_image_free);
    if (!data) throw InputError(name, 0, std::string("cannot decode the image (") + stbi_failure_reason() + ")");
    Texture t;
    t.name = name;
    t.width = w;
    t.height = h;
    t.texels.assign(data.get(), data.get() + std::size_t(w) * std::size_t(h) * 3);
    return t;
}

Texture load_texture(const std::string& path) {
    const std::string bytes = read_file(path, 1ull << 30);
    return decode_texture({reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()}, path);
}

}  // namespace arbor::engine
