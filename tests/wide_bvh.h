#pragma once
/// bvh-sah with only the SIMD layouts at one width N: the accel the wide-walk tests
/// (test_wide_root, test_plain_traversal) call trace_from / trace_root on directly.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths_impl.h"

#include <doctest/doctest.h>

#include <memory>

namespace arbor::testing {

template <std::size_t N> std::unique_ptr<accel::Accel> wide_bvh(const accel::TriangleView& view) {
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;
    cfg.wide.width = N;
    auto acc = accel::make_accel(accel::AccelKind::bvh_sah, view, cfg);
    REQUIRE(dynamic_cast<const accel::WideBvhAccel<N>*>(acc.get()) != nullptr);
    return acc;
}

}  // namespace arbor::testing
