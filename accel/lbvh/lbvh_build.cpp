#include "accel/lbvh/lbvh_build.h"

#include "accel/lbvh/morton.h"
#include "accel/lbvh/radix_sort.h"
#include "accel/util/scratch_array.h"
#include "accel/util/timer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

namespace arbor::accel {

namespace {

/// Elements per parallel_for chunk of the streaming passes (codes, gather).
constexpr std::size_t grain = 8192;

template <class Fn>
void parallel_range(std::size_t n, Fn&& fn) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
    });
}

/// Sorts every run of at least `min_run` keys with equal codes (bits 32..61) by fine[index] (the
/// full 63-bit code of the reference in the low 32 bits), keeping index order among equal codes,
/// and marks it with bit 62 (radix_tree.h). Shorter runs end up inside one leaf whatever their
/// order (a node either holds a whole run or lies inside it), so they keep index order and save
/// the work. Each run is owned by the block holding its first key. Returns scratch bytes.
std::size_t refine_runs(std::span<std::uint64_t> keys, std::span<const std::uint64_t> fine, std::size_t min_run,
                        int digit_bits) {
    const std::size_t n = keys.size();
    constexpr std::uint64_t mark = std::uint64_t(1) << 62;
    constexpr std::size_t block = 1 << 14;
    constexpr std::size_t large_run = 1 << 12;  // longer runs use the parallel radix sort
    min_run = std::max<std::size_t>(min_run, 2);
    auto code = [&](std::size_t i) { return (keys[i] >> 32) & 0x3fffffffu; };
    // Pass 1 (read only): the long runs, listed per block of their first key.
    const std::size_t blocks = (n + block - 1) / block;
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> found(blocks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b)
            for (std::size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i) {
                if (i > 0 && code(i - 1) == code(i)) continue;  // not the start of a run
                std::size_t j = i + 1;
                while (j < n && code(j) == code(i)) ++j;
                if (j - i >= min_run) found[b].push_back({i, j});
            }
    });
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    for (const auto& f : found) runs.insert(runs.end(), f.begin(), f.end());
    // Pass 2: sort each run on its own (runs are disjoint).
    std::size_t scratch = runs.size() * sizeof(runs[0]);
    for (const auto& [i, j] : runs) scratch = std::max(scratch, (j - i) * 12);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs;
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
            const auto [i, j] = runs[k];
            const std::uint64_t head = mark | (keys[i] & (std::uint64_t(0x3fffffffu) << 32));
            if (j - i < large_run) {
                pairs.clear();
                for (std::size_t p = i; p < j; ++p) pairs.push_back({fine[std::uint32_t(keys[p])], std::uint32_t(keys[p])});
                std::sort(pairs.begin(), pairs.end());  // (code, index) pairs are unique
                for (std::size_t p = i; p < j; ++p) keys[p] = head | pairs[p - i].second;
            } else {
                ScratchArray<std::uint64_t> codes(j - i);
                ScratchArray<std::uint32_t> ids(j - i);
                for (std::size_t p = i; p < j; ++p) ids[p - i] = std::uint32_t(keys[p]), codes[p - i] = fine[ids[p - i]];
                RadixSortConfig cfg;
                cfg.digit_bits = digit_bits;
                cfg.end_bit = 33;  // the top 30 bits are equal in the run
                radix_sort(codes.span(), ids.span(), cfg);
                for (std::size_t p = i; p < j; ++p) keys[p] = head | ids[p - i];
            }
        }
    });
    return scratch;
}

}  // namespace

BinaryBvh build_lbvh(BuildPrims&& prims, const BvhBuildConfig& cfg) {
    const BuildPrims input = std::move(prims);
    return build_lbvh(input, cfg, LbvhOptions{});
}

BinaryBvh build_lbvh(const PrimRefs& refs, const BvhBuildConfig& cfg) { return build_lbvh(make_build_prims(refs), cfg); }

BinaryBvh build_lbvh(const PrimRefs& refs, const BvhBuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings) {
    return build_lbvh(make_build_prims(refs), cfg, opt, timings);
}

BinaryBvh build_lbvh(const BuildPrims& input, const BvhBuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings) {
    BinaryBvh bvh;
    bvh.dropped_nonfinite = input.dropped_nonfinite;
    const std::size_t n = input.size();
    if (n == 0) return bvh;
    if (n >= std::size_t(1) << 31) throw std::invalid_argument("lbvh: more than 2^31 - 1 triangles");
    LbvhTimings local;
    LbvhTimings& t = timings ? *timings : local;
    const std::uint32_t max_leaf = std::max(cfg.max_leaf_size, cfg.leaf_floor);

    // 1. Codes. Packed modes put the (top 30) code bits and the reference index in one key
    //    (code << 32 | index), so the sort moves 8 bytes per element; bits63 carries the index
    //    as a value. bits63_refined keeps the full codes per reference for the refinement.
    Timer step;
    const bool packed = opt.codes != MortonSort::bits63;
    const bool refined = opt.codes == MortonSort::bits63_refined;
    const MortonQuantizer quantizer(input.centroid_bounds, opt.codes == MortonSort::bits30 ? 10 : 21);
    // Scratch is not zeroed: every element is written below.
    ScratchArray<std::uint64_t> keys(n), fine(refined ? n : 0);
    ScratchArray<std::uint32_t> values(packed ? 0 : n);
    if (opt.codes == MortonSort::bits30) {
        parallel_range(n, [&](std::size_t i) {
            keys[i] = (std::uint64_t(quantizer.code30(input.prims[i].centroid())) << 32) | std::uint64_t(i);
        });
    } else if (refined) {
        // The top 30 bits of a 63-bit code are exactly the 30-bit code (both quantizations scale
        // by powers of two of the same factor), so the prefix order is the 30-bit order.
        parallel_range(n, [&](std::size_t i) {
            const std::uint64_t code = quantizer.code63(input.prims[i].centroid());
            fine[i] = code;
            keys[i] = ((code >> 33) << 32) | std::uint64_t(i);
        });
    } else {
        parallel_range(n, [&](std::size_t i) {
            keys[i] = quantizer.code63(input.prims[i].centroid());
            values[i] = std::uint32_t(i);
        });
    }
    t.codes_ms = step.ms();

    // 2. Stable sort: equal codes keep index order, so (code, index) is sorted as one key.
    step = Timer();
    RadixSortConfig sort_cfg;
    sort_cfg.digit_bits = opt.digit_bits;
    sort_cfg.begin_bit = packed ? 32 : 0;
    sort_cfg.end_bit = packed ? 62 : 63;
    std::size_t sort_bytes = radix_sort(keys.span(), values.span(), sort_cfg);
    if (refined) sort_bytes = std::max(sort_bytes, refine_runs(keys.span(), fine.span(), max_leaf + 1, opt.digit_bits));
    t.sort_ms = step.ms();

    // 3. Hierarchy. The leaves read the boxes and triangle ids through the sorted references (no
    //    separate gather pass); leaf ranges are sorted positions, the order of prim_ids.
    step = Timer();
    RadixTreeInput in;
    in.keys = std::span<const std::uint64_t>(keys.data(), n);
    in.code_shift = packed ? 32 : 0;
    in.sorted_refs = values.span();
    in.fine_codes = fine.span();
    in.prims = std::span<const BuildPrim>(input.prims.data(), input.size());
    in.max_leaf_size = max_leaf;
    in.parallel_threshold = cfg.parallel_threshold;
    in.sah_collapse = opt.sah_collapse;
    in.traversal_cost = cfg.traversal_cost;
    in.intersection_cost = cfg.intersection_cost;
    RadixTreeResult tree = build_radix_tree(in, opt.hierarchy);
    bvh.nodes = std::move(tree.nodes);
    bvh.prim_ids = std::move(tree.prim_ids);
    t.hierarchy_ms = step.ms();

    const std::size_t key_bytes = keys.bytes() + values.bytes() + fine.bytes();
    const std::size_t sort_peak = key_bytes + sort_bytes;
    const std::size_t tree_peak = key_bytes + tree.temp_bytes + bvh.prim_ids.size() * sizeof(std::uint32_t) +
                                  bvh.nodes.size() * sizeof(BvhBuildNode);
    bvh.build_peak_bytes = input.memory_bytes() + std::max(sort_peak, tree_peak);
    return bvh;
}

}  // namespace arbor::accel
