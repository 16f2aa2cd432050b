#include "engine/image_output.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>

namespace arbor::engine {

namespace {

std::string extension_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string png_beside(const std::string& path) {
    return std::filesystem::path(path).replace_extension(".png").string();
}

}  // namespace

std::optional<OutputFormat> output_format(const std::string& path) {
    const std::string ext = extension_of(path);
    if (ext == ".exr") return OutputFormat::exr;
    if (ext == ".png") return OutputFormat::png;
    if (ext == ".pfm") return OutputFormat::pfm;
    return std::nullopt;
}

std::string output_problem(const std::string& path) {
    if (path.empty()) return "empty output path";
    if (!output_format(path)) {
        const std::string ext = extension_of(path);
        return "'" + path + "': " + (ext.empty() ? "no extension" : "unknown output format " + ext) +
               " (expected .exr, .png or .pfm)";
    }
    const std::filesystem::path p(path);
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        return "'" + path + "': the folder '" + dir.string() + "' does not exist";
    if (std::filesystem::is_directory(p, ec)) return "'" + path + "' is a folder";
    // access(W_OK) says yes to root everywhere; creating a file is the real test (read-only file
    // systems, /proc, permissions).
    const std::string probe = (dir / (".arbor-write-test-" + std::to_string(::getpid()))).string();
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0)
        return "'" + path + "': cannot write in the folder '" + dir.string() + "' (" + std::strerror(errno) + ")";
    ::close(fd);
    ::unlink(probe.c_str());
    return {};
}

std::vector<std::string> write_outputs(const std::string& path, const Image& img, const OutputOptions& opt) {
    const auto format = output_format(path);
    if (!format) throw InputError(output_problem(path));
    switch (*format) {
    case OutputFormat::exr: {
        write_exr(path, img);
        if (!opt.png_preview) return {path};
        const std::string png = png_beside(path);
        write_png_preview(png, img, opt.exposure);
        return {path, png};
    }
    case OutputFormat::png: write_png_preview(path, img, opt.exposure); return {path};
    case OutputFormat::pfm: write_pfm(path, img); return {path};
    }
    return {};
}

void write_pfm(const std::string& path, const Image& img) {
    const int r = img.channel("R"), g = img.channel("G"), b = img.channel("B");
    if (r < 0 || g < 0 || b < 0) throw InputError(path, 0, "image has no R, G, B channels");
    std::string bytes = "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    const std::size_t header = bytes.size();
    bytes.resize(header + std::size_t(img.width) * std::size_t(img.height) * 12);
    char* out = bytes.data() + header;
    static_assert(std::endian::native == std::endian::little, "PFM with scale -1 is little-endian");
    for (int y = img.height - 1; y >= 0; --y)  // PFM stores the bottom row first
        for (int x = 0; x < img.width; ++x) {
            const float px[3] = {img.at(r, x, y), img.at(g, x, y), img.at(b, x, y)};
            std::memcpy(out, px, sizeof px);
            out += sizeof px;
        }
    write_file_atomic(path, bytes);
}

Image read_pfm(const std::string& path) {
    const std::string data = read_file(path);
    int w = 0, h = 0;
    float scale = 0.0f;
    int consumed = 0;
    if (std::sscanf(data.c_str(), "PF %d %d %f%n", &w, &h, &scale, &consumed) != 3 || w < 1 || h < 1 || scale >= 0.0f ||
        std::size_t(consumed) >= data.size())
        throw InputError(path, 0, "not a little-endian colour PFM");
    const std::size_t start = std::size_t(consumed) + 1;  // one whitespace byte after the scale
    if (data.size() - start != std::size_t(w) * std::size_t(h) * 12) throw InputError(path, 0, "PFM size does not match its header");
    Image img(w, h, {"R", "G", "B"});
    const char* in = data.data() + start;
    for (int y = h - 1; y >= 0; --y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c, in += 4) std::memcpy(&img.at(c, x, y), in, 4);
    return img;
}

std::uint64_t output_image_bytes(int width, int height, std::size_t channels, bool png) {
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    return pixels * (4 * channels + (png ? 3 : 0));
}

}  // namespace arbor::engine
