#pragma once
/// MemoryLimitError: a build that would need more memory than BuildConfig::max_memory. Thrown
/// before allocating by the factory's estimate (factory/memory_estimate.h) and by the kd-tree
/// builder as it grows. One line: the structure, the bytes needed (or reached) and the limit.
#include <stdexcept>

namespace arbor::accel {

struct MemoryLimitError : std::length_error {
    using std::length_error::length_error;
};

}  // namespace arbor::accel
