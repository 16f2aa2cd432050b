#pragma once
/// accel's names for the ray records and the traceable rule of simd/ray.h (defined there, once, so
/// that the SIMD kernels below accel share them).
#include "simd/ray.h"

namespace arbor::accel {

using simd::Hit;
using simd::hits_agree;
using simd::invalid_prim;
using simd::miss_hit;
using simd::Ray;
using simd::ray_is_traceable;
using simd::Vec3f;

}  // namespace arbor::accel
