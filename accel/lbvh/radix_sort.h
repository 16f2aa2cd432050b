#pragma once
/// Parallel stable LSD radix sort of (key, value) pairs (oneTBB has none: tbb::parallel_sort is a
/// comparison sort, neither stable nor deterministic).
///
/// Each pass: per-block digit histograms (tbb::parallel_for over fixed blocks) -> one exclusive
/// scan in (digit, block) order -> every block scatters its elements in input order to its own
/// offsets. Blocks depend only on the input size, never on the thread count, and a stable sort has
/// exactly one result, so the output is the same for any number of threads.
#include <cstddef>
#include <cstdint>
#include <span>

namespace arbor::accel {

struct RadixSortConfig {
    /// Bits per pass: 8 (256 buckets) or 11 (2048 buckets); 1..16 accepted. See perf/ for the
    /// measurement behind the default.
    int digit_bits = 8;
    /// Only bits [begin_bit, end_bit) of the key are sorted on (the other bits may hold payload,
    /// e.g. an index packed under a 30-bit Morton code). end_bit is clamped to the key width.
    int begin_bit = 0;
    int end_bit = 64;
    /// Elements per block (the unit of parallel work); the last block may be smaller.
    std::size_t block_size = std::size_t(1) << 16;
};

/// Sorts keys ascending (by bits [begin_bit, end_bit)), carrying values[i] along with keys[i];
/// equal keys keep their input order. values may be empty (keys only); otherwise its size must
/// equal keys.size() (std::invalid_argument if not). Passes whose digit is the same in every key
/// are skipped. Uses tbb::parallel_for in the current arena; allocates scratch the size of the
/// input. Returns the scratch bytes it allocated (for build peak memory).
std::size_t radix_sort(std::span<std::uint32_t> keys, std::span<std::uint32_t> values, const RadixSortConfig& cfg = {});
std::size_t radix_sort(std::span<std::uint64_t> keys, std::span<std::uint32_t> values, const RadixSortConfig& cfg = {});

}  // namespace arbor::accel
