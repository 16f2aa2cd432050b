#pragma once
/// Diffuse textures: images decoded by stb_image (PNG, JPEG, BMP, TGA, ...), kept as 8-bit sRGB
/// and looked up bilinearly in linear RGB (each texel is converted by a table before blending,
/// as a GPU's sRGB texture does).
#include "accel/core/geometry.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace arbor::engine {

using accel::Vec3f;

struct Vec2f {
    float u = 0.0f, v = 0.0f;
};

struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<std::uint8_t> texels;  ///< RGB, 8-bit sRGB, row 0 = the image's top row

    /// Linear RGB at texture coordinate (u, v): v = 0 is the image's bottom (OBJ and OpenGL; glTF's
    /// v = 0 at the top is turned over by the loader), bilinear between texel centres, repeating
    /// outside [0, 1). Non-finite coordinates give texel (0, 0).
    Vec3f sample(float u, float v) const;
};

/// Largest texture side accepted; bigger images are refused (as a warning by the loaders).
inline constexpr int max_texture_side = 16384;

/// Decodes an image file's bytes; throws InputError naming `name` for data stb_image cannot
/// decode or a side above max_texture_side.
Texture decode_texture(std::span<const unsigned char> bytes, const std::string& name);
/// Reads and decodes `path`.
Texture load_texture(const std::string& path);

/// The sRGB transfer function inverted (IEC 61966-2-1): 8-bit code -> linear value.
float srgb_to_linear(std::uint8_t code);

}  // namespace arbor::engine
