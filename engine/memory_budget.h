#pragma once
/// How much memory a command may use for its input and its structure, and byte sizes as people
/// write them ("2G", "512M"), for `--max-memory`.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace arbor::engine {

/// Physical memory of the machine in bytes (sysconf), or 2^64-1 when it cannot be told.
std::uint64_t physical_memory_bytes();
/// `max_bytes` when non-zero, otherwise physical_memory_bytes().
std::uint64_t memory_budget(std::uint64_t max_bytes);

/// Parses "1234", "64K", "512M", "2G", "1.5T" (powers of 1024; an optional trailing "B" or "iB";
/// case-insensitive). nullopt for anything else, for 0 and for values beyond 2^64-1.
std::optional<std::uint64_t> parse_byte_size(std::string_view s);
/// "812 B", "3.2 KiB", "1.5 GiB": for messages.
std::string format_bytes(std::uint64_t bytes);

}  // namespace arbor::engine
