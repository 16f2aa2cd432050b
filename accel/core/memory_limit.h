#pragma once
/// MemoryLimitError: a build that would need more memory than BuildConfig::max_memory. Thrown
/// before allocating: by the factory's estimate (factory/memory_estimate.h), by the BVHs' layouts
/// from their exact sizes (BvhAccel::init, WideConfig::max_bytes) and by the kd-tree builder as it
/// grows. One line: the structure, the bytes needed (or reached) and the limit.
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace arbor::accel {

struct MemoryLimitError : std::length_error {
    using std::length_error::length_error;
};

/// Bytes as the errors write them: "36.9 MiB".
inline std::string mib_text(std::uint64_t bytes) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / 1048576.0);
    return buf;
}

/// The limit as the errors name it: "max_memory = 45.0 MiB (47185920 bytes)".
inline std::string max_memory_text(std::uint64_t max_memory) {
    return "max_memory = " + mib_text(max_memory) + " (" + std::to_string(max_memory) + " bytes)";
}

}  // namespace arbor::accel
