#include "accel/lbvh/radix_sort.h"

#include "accel/util/scratch_array.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace arbor::accel {

namespace {

/// One pass over blocks [0, nblocks): fn(block, begin, end), in parallel.
template <class Fn>
void for_blocks(std::size_t n, std::size_t block, Fn&& fn) {
    const std::size_t nblocks = (n + block - 1) / block;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nblocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) fn(b, b * block, std::min(n, (b + 1) * block));
    });
}

template <class Key>
std::size_t sort_impl(std::span<Key> keys, std::span<std::uint32_t> values, const RadixSortConfig& cfg) {
    if (!values.empty() && values.size() != keys.size())
        throw std::invalid_argument("radix_sort: values.size() != keys.size()");
    const std::size_t n = keys.size();
    if (n <= 1) return 0;
    constexpr int key_bits = int(sizeof(Key) * 8);
    const int begin_bit = std::clamp(cfg.begin_bit, 0, key_bits);
    const int end_bit = std::clamp(cfg.end_bit, begin_bit, key_bits);
    const int digit_bits = std::clamp(cfg.digit_bits, 1, 16);
    const std::size_t radix = std::size_t(1) << digit_bits;
    const std::size_t block = std::max<std::size_t>(cfg.block_size, 1);
    const std::size_t nblocks = (n + block - 1) / block;
    const bool with_values = !values.empty();

    // Scratch: not zeroed; every element is written by the first scatter.
    ScratchArray<Key> tmp_keys(n);
    ScratchArray<std::uint32_t> tmp_values(with_values ? n : 0);
    // counts[b * radix + d]: how many keys of block b have digit d; turned into offsets in place.
    std::vector<std::size_t> counts(nblocks * radix);
    std::size_t scratch = n * sizeof(Key) + (with_values ? n * sizeof(std::uint32_t) : 0) + counts.size() * sizeof(std::size_t);

    Key* src_k = keys.data();
    Key* dst_k = tmp_keys.data();
    std::uint32_t* src_v = values.data();
    std::uint32_t* dst_v = tmp_values.data();

    for (int shift = begin_bit; shift < end_bit; shift += digit_bits) {
        const Key mask = Key((std::size_t(1) << std::min(digit_bits, end_bit - shift)) - 1);
        for_blocks(n, block, [&](std::size_t b, std::size_t lo, std::size_t hi) {
            std::size_t* c = counts.data() + b * radix;
            std::fill(c, c + radix, std::size_t(0));
            for (std::size_t i = lo; i < hi; ++i) ++c[(src_k[i] >> shift) & mask];
        });
        // Exclusive scan in (digit, block) order: block b's keys with digit d go after all keys
        // with smaller digits and after the keys with digit d of blocks before b (stability).
        std::size_t sum = 0;
        bool constant = false;
        for (std::size_t d = 0; d < radix; ++d) {
            const std::size_t before = sum;
            for (std::size_t b = 0; b < nblocks; ++b) {
                std::size_t& c = counts[b * radix + d];
                const std::size_t count = c;
                c = sum;
                sum += count;
            }
            if (sum - before == n) constant = true;  // every key has digit d: the pass is the identity
        }
        if (constant) continue;
        for_blocks(n, block, [&](std::size_t b, std::size_t lo, std::size_t hi) {
            std::size_t* off = counts.data() + b * radix;
            if (with_values) {
                for (std::size_t i = lo; i < hi; ++i) {
                    const std::size_t pos = off[(src_k[i] >> shift) & mask]++;
                    dst_k[pos] = src_k[i];
                    dst_v[pos] = src_v[i];
                }
            } else {
                for (std::size_t i = lo; i < hi; ++i) dst_k[off[(src_k[i] >> shift) & mask]++] = src_k[i];
            }
        });
        std::swap(src_k, dst_k);
        std::swap(src_v, dst_v);
    }
    if (src_k != keys.data()) {  // an odd number of passes ran: the result is in the scratch
        for_blocks(n, block, [&](std::size_t, std::size_t lo, std::size_t hi) {
            std::copy(src_k + lo, src_k + hi, keys.data() + lo);
            if (with_values) std::copy(src_v + lo, src_v + hi, values.data() + lo);
        });
    }
    return scratch;
}

}  // namespace

std::size_t radix_sort(std::span<std::uint32_t> keys, std::span<std::uint32_t> values, const RadixSortConfig& cfg) {
    return sort_impl(keys, values, cfg);
}

std::size_t radix_sort(std::span<std::uint64_t> keys, std::span<std::uint32_t> values, const RadixSortConfig& cfg) {
    return sort_impl(keys, values, cfg);
}

}  // namespace arbor::accel
