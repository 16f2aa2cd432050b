// Precompiled for every large arbor target when ARBOR_PCH is on (cmake/ArborPch.cmake): the
// standard and third-party headers nearly every file includes. With -march=native a plain include
// of xsimd parses ~170k lines (the compiler's own AVX-512 intrinsics headers among them): 70-80% of
// an ordinary file's compile time. Nothing of arbor's own goes here, so editing an arbor header
// never rebuilds it, and every file still includes what it uses (builds with ccache leave
// ARBOR_PCH off and check that).
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <xsimd/xsimd.hpp>
