#pragma once
/// .rays / .hits files of ../shared/spec/rayfile.md (little-endian, 16-byte header, fixed records).
#include "accel/core/ray.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace arbor::engine {

/// Reads a ray file. Everything is checked before the records are allocated: a bad magic, an
/// unknown version, a file shorter or longer than 16 + 32*N bytes, or records needing more than
/// `max_bytes` (0: the machine's physical memory, see memory_budget.h) throw InputError.
std::vector<accel::Ray> read_rays(const std::string& path, std::uint64_t max_bytes = 0);
std::vector<accel::Hit> read_hits(const std::string& path, std::uint64_t max_bytes = 0);

/// The same checks on a file already in memory (`name` is used in messages).
std::vector<accel::Ray> parse_rays(std::span<const unsigned char> bytes, const std::string& name);
std::vector<accel::Hit> parse_hits(std::span<const unsigned char> bytes, const std::string& name);

/// Writes atomically (temporary file + rename).
void write_rays(const std::string& path, std::span<const accel::Ray> rays);
void write_hits(const std::string& path, std::span<const accel::Hit> hits);

}  // namespace arbor::engine
