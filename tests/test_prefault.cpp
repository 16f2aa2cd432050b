// prefault / resize_prefaulted: mapping pages ahead of the writes changes no value and no size.
#include "accel/util/prefault.h"
#include "accel/util/uninit_vector.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <numeric>
#include <vector>

using namespace arbor::accel;

TEST_CASE("prefault: resize_prefaulted keeps the old elements and gives the new size, small and big") {
    for (std::size_t n : {std::size_t(0), std::size_t(10), std::size_t(3) << 20}) {  // 3M floats: 12 MB, prefaulted
        std::vector<float> v(5);
        std::iota(v.begin(), v.end(), 1.0f);
        resize_prefaulted(v, n + 5);
        CHECK(v.size() == n + 5);
        for (int i = 0; i < 5; ++i) CHECK(v[i] == float(i + 1));
        if (n > 0) CHECK(v.back() == 0.0f);  // std::vector value-initializes the new elements
        UninitVector<std::uint32_t> u;
        resize_prefaulted(u, n);
        CHECK(u.size() == n);
        for (std::size_t i = 0; i < n; ++i) u[i] = std::uint32_t(i);  // every page writable
        if (n > 0) CHECK(u[n - 1] == n - 1);
        resize_prefaulted(u, n / 2);  // shrinking is a plain resize
        CHECK(u.size() == n / 2);
    }
}

TEST_CASE("prefault: unaligned, tiny and empty ranges are accepted and leave the memory as it was") {
    std::vector<unsigned char> buf((std::size_t(5) << 20) + 123, 7);
    prefault(buf.data() + 1, buf.size() - 2);  // starts and ends inside a page
    prefault(buf.data(), 0);
    prefault(nullptr, 0);
    prefault(buf.data() + 3, 100);
    for (std::size_t i = 0; i < buf.size(); i += 4093) CHECK(buf[i] == 7);
    CHECK(buf.back() == 7);
}
