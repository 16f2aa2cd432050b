// The radix sort against its oracle, std::stable_sort, on the key distributions that break sorts:
// random, few distinct values, all equal, sorted, reversed, tiny and odd sizes; and the same
// output at 1 and 2 threads.
#include "accel/lbvh/radix_sort.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

using namespace arbor;
using accel::RadixSortConfig;

namespace {

template <class Key>
std::vector<Key> make_keys(const std::string& kind, std::size_t n, std::uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Key> k(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t r = rng();
        if (kind == "random") k[i] = Key(r);
        else if (kind == "duplicates") k[i] = Key(r % 7) << (sizeof(Key) * 8 - 3);  // high bits only
        else if (kind == "few-low") k[i] = Key(r % 5);
        else if (kind == "equal") k[i] = Key(0x1234567890abcdefull);
        else if (kind == "sorted") k[i] = Key(i * 3);
        else if (kind == "reverse") k[i] = Key(n - i);
    }
    return k;
}

/// Sorts (key, index) pairs with both sorts and requires identical keys and values.
template <class Key>
void check_against_stable_sort(std::vector<Key> keys, const RadixSortConfig& cfg, bool with_values = true) {
    const int kb = int(sizeof(Key) * 8);
    const int lo = std::clamp(cfg.begin_bit, 0, kb), hi = std::clamp(cfg.end_bit, lo, kb);
    auto sort_key = [&](Key k) {
        const Key m = hi - lo >= kb ? Key(~Key(0)) : Key((Key(1) << (hi - lo)) - 1);
        return Key((k >> lo) & m);
    };
    std::vector<std::uint32_t> idx(keys.size());
    std::iota(idx.begin(), idx.end(), 0u);
    std::vector<std::uint32_t> expect_idx = idx;
    std::stable_sort(expect_idx.begin(), expect_idx.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return sort_key(keys[a]) < sort_key(keys[b]); });
    std::vector<Key> expect_keys(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) expect_keys[i] = keys[expect_idx[i]];

    std::vector<std::uint32_t> values = with_values ? idx : std::vector<std::uint32_t>{};
    accel::radix_sort(std::span<Key>(keys), std::span<std::uint32_t>(values), cfg);
    CHECK(keys == expect_keys);
    if (with_values) CHECK(values == expect_idx);
}

}  // namespace

TEST_CASE_TEMPLATE("radix_sort: matches std::stable_sort", Key, std::uint32_t, std::uint64_t) {
    for (const char* kind : {"random", "duplicates", "few-low", "equal", "sorted", "reverse"}) {
        for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(3), std::size_t(257),
                              std::size_t(20011)}) {
            for (int digit_bits : {8, 11, 5}) {
                for (std::size_t block : {std::size_t(64), std::size_t(1000), std::size_t(1) << 16}) {
                    CAPTURE(kind);
                    CAPTURE(n);
                    CAPTURE(digit_bits);
                    CAPTURE(block);
                    RadixSortConfig cfg;
                    cfg.digit_bits = digit_bits;
                    cfg.block_size = block;
                    check_against_stable_sort(make_keys<Key>(kind, n, std::uint32_t(n + digit_bits)), cfg);
                }
            }
        }
    }
}

TEST_CASE("radix_sort: keys only, and a bit range leaves the other bits as payload") {
    RadixSortConfig cfg;
    cfg.block_size = 500;
    check_against_stable_sort(make_keys<std::uint64_t>("random", 10007, 9), cfg, false);
    check_against_stable_sort(make_keys<std::uint32_t>("duplicates", 10007, 9), cfg, false);
    // Sort on the upper 30 bits of (code << 32 | index): the LBVH packing. Equal codes must come
    // out in input order, which here differs from payload order (the payload is random).
    cfg.begin_bit = 32;
    cfg.end_bit = 62;
    std::mt19937 rng(3);
    std::vector<std::uint64_t> packed(30001);
    for (auto& k : packed) k = (std::uint64_t(rng() % 1000) << 32) | rng();
    check_against_stable_sort(packed, cfg);
    check_against_stable_sort(packed, cfg, false);
    // Middle bits only, with an odd digit count that does not divide the range.
    cfg.begin_bit = 7;
    cfg.end_bit = 20;
    cfg.digit_bits = 6;
    check_against_stable_sort(make_keys<std::uint32_t>("random", 4099, 4), cfg);
}

TEST_CASE("radix_sort: a values span of the wrong size is rejected") {
    std::vector<std::uint32_t> keys(10), values(9);
    CHECK_THROWS_AS(accel::radix_sort(std::span<std::uint32_t>(keys), std::span<std::uint32_t>(values)),
                    std::invalid_argument);
}

TEST_CASE("radix_sort: constant digits are skipped, but a single differing key is still sorted") {
    // All keys equal except one in the middle: every pass but one sees a constant digit.
    std::vector<std::uint64_t> keys(5000, 0xffff'0000'0000'0000ull);
    keys[2500] = 0x0000'0000'0000'0001ull;
    RadixSortConfig cfg;
    cfg.block_size = 128;
    check_against_stable_sort(keys, cfg);
}

TEST_CASE("radix_sort: the same output with 1 and 2 threads") {
    auto run = [](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        auto keys = make_keys<std::uint64_t>("few-low", 100000, 17);
        for (std::size_t i = 0; i < keys.size(); i += 3) keys[i] ^= std::uint64_t(i) << 40;
        std::vector<std::uint32_t> values(keys.size());
        std::iota(values.begin(), values.end(), 0u);
        RadixSortConfig cfg;
        cfg.block_size = 4096;
        accel::radix_sort(std::span<std::uint64_t>(keys), std::span<std::uint32_t>(values), cfg);
        return std::make_pair(keys, values);
    };
    const auto one = run(1), two = run(2);
    CHECK(one.first == two.first);
    CHECK(one.second == two.second);
    CHECK(std::is_sorted(one.first.begin(), one.first.end()));
}
