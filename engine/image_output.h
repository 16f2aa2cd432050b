#pragma once
/// What `arbor render -o PATH` writes, told by PATH's extension (spec/cli.md): `.exr` (every
/// channel, float, plus a PNG preview beside it), `.png` (8-bit sRGB only) or `.pfm` (float RGB).
/// Checked before anything is rendered: an unknown extension or a folder that does not exist or
/// cannot be written is refused with a message naming the user's path. Every file is written to a
/// temporary file and renamed.
#include "engine/image.h"

#include <optional>
#include <string>
#include <vector>

namespace arbor::engine {

enum class OutputFormat { exr, png, pfm };

/// The format of `path` by its extension (case-insensitive), or nullopt.
std::optional<OutputFormat> output_format(const std::string& path);

/// Empty when `path` can be an output: a known extension and an existing, writable folder. Else a
/// one-line problem naming `path` ("'x.jpg': unknown output format .jpg (expected .exr, .png or .pfm)").
std::string output_problem(const std::string& path);

struct OutputOptions {
    bool png_preview = true;  ///< .exr: also write PATH with extension .png
    float exposure = 0.0f;    ///< EV: the 8-bit PNG shows radiance x 2^EV (float outputs keep radiance)
};

/// Writes `img` to `path` in its format (InputError for an unknown extension or a failed write);
/// returns the paths written, the main file first.
std::vector<std::string> write_outputs(const std::string& path, const Image& img, const OutputOptions& opt = {});

/// Channels R, G, B as a Portable Float Map ("PF", little-endian, rows bottom to top).
void write_pfm(const std::string& path, const Image& img);
/// Reads a PFM written by write_pfm (three channels R, G, B); InputError on anything else.
Image read_pfm(const std::string& path);

/// Bytes the image of a render with `channels` channels and its outputs hold at their peak: the
/// float planes, plus the 8-bit PNG buffer when one is written.
std::uint64_t output_image_bytes(int width, int height, std::size_t channels, bool png);

}  // namespace arbor::engine
