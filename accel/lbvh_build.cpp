#include "accel/lbvh_build.h"

#include "accel/morton.h"
#include "accel/radix_sort.h"
#include "accel/scratch_array.h"
#include "accel/timer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

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

}  // namespace

BinaryBvh build_lbvh(const PrimRefs& refs, const BuildConfig& cfg) { return build_lbvh(refs, cfg, LbvhOptions{}); }

BinaryBvh build_lbvh(const PrimRefs& refs, const BuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings) {
    BinaryBvh bvh;
    bvh.dropped_nonfinite = refs.dropped_nonfinite;
    const std::size_t n = refs.size();
    if (n == 0) return bvh;
    if (n >= std::size_t(1) << 31) throw std::invalid_argument("lbvh: more than 2^31 - 1 triangles");
    if (opt.morton_bits != 30 && opt.morton_bits != 63) throw std::invalid_argument("lbvh: morton_bits must be 30 or 63");
    LbvhTimings local;
    LbvhTimings& t = timings ? *timings : local;

    // 1. Codes. With 30 bits the code and the reference index share one key (code << 32 | index),
    //    so the sort moves 8 bytes per element; with 63 bits the index travels as a value.
    Timer step;
    const bool packed = opt.morton_bits == 30;
    const MortonQuantizer quantizer(refs.centroid_bounds, packed ? 10 : 21);
    // Scratch is not zeroed: every element is written below.
    ScratchArray<std::uint64_t> keys(n);
    ScratchArray<std::uint32_t> values(packed ? 0 : n);
    if (packed) {
        parallel_range(n, [&](std::size_t i) {
            keys[i] = (std::uint64_t(quantizer.code30(refs.centroid(i))) << 32) | std::uint64_t(i);
        });
    } else {
        parallel_range(n, [&](std::size_t i) {
            keys[i] = quantizer.code63(refs.centroid(i));
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
    const std::size_t sort_bytes = radix_sort(keys.span(), values.span(), sort_cfg);
    t.sort_ms = step.ms();

    // 3. Hierarchy. The leaves read the boxes and triangle ids through the sorted references (no
    //    separate gather pass); leaf ranges are sorted positions, the order of prim_ids.
    step = Timer();
    RadixTreeInput in;
    in.keys = std::span<const std::uint64_t>(keys.data(), n);
    in.code_shift = packed ? 32 : 0;
    in.sorted_refs = values.span();
    in.prims = &refs;
    in.max_leaf_size = cfg.max_leaf_size;
    in.parallel_threshold = cfg.parallel_threshold;
    RadixTreeResult tree = build_radix_tree(in, opt.hierarchy);
    bvh.nodes = std::move(tree.nodes);
    bvh.prim_ids = std::move(tree.prim_ids);
    t.hierarchy_ms = step.ms();

    const std::size_t key_bytes = n * (sizeof(std::uint64_t) + (packed ? 0 : sizeof(std::uint32_t)));
    const std::size_t sort_peak = key_bytes + sort_bytes;
    const std::size_t tree_peak = key_bytes + tree.temp_bytes + bvh.prim_ids.size() * sizeof(std::uint32_t) +
                                  bvh.nodes.size() * sizeof(BvhBuildNode);
    bvh.build_peak_bytes = refs.memory_bytes() + std::max(sort_peak, tree_peak);
    return bvh;
}

}  // namespace arbor::accel
