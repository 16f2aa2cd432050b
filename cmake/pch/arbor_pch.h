// Precompiled for every large arbor target when ARBOR_PCH is on (cmake/ArborPch.cmake): xsimd and
// the standard headers nearly every file includes. With -march=native xsimd alone parses ~170k lines
// (the compiler's own AVX-512 intrinsics headers among them): 70-80% of an ordinary file's compile
// time. Kept lean: loading a precompiled header costs time by its size (90 MB with gcc), and with
// <filesystem>, <random>, <map>, <functional> and TBB's headers too (132 MB) small files compiled
// up to twice as slowly as with this one, large ones no faster. Nothing of arbor's own goes here,
// so editing an arbor header never rebuilds it; every file still includes what it uses (builds
// without ARBOR_PCH, e.g. with ccache, check that).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <xsimd/xsimd.hpp>
