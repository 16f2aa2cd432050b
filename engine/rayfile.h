#pragma once
/// .rays / .hits files of ../shared/spec/rayfile.md (little-endian, 16-byte header, fixed records).
#include "accel/ray.h"

#include <span>
#include <string>
#include <vector>

namespace arbor::engine {

/// Reads a ray file. The size is checked against the header before anything is allocated: a bad
/// magic, an unknown version, or a file shorter or longer than 16 + 32*N bytes throws InputError.
std::vector<accel::Ray> read_rays(const std::string& path);
std::vector<accel::Hit> read_hits(const std::string& path);

/// Writes atomically (temporary file + rename).
void write_rays(const std::string& path, std::span<const accel::Ray> rays);
void write_hits(const std::string& path, std::span<const accel::Hit> hits);

}  // namespace arbor::engine
