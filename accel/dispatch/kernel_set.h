#pragma once
/// The SIMD kernel set the structures' SIMD paths run on (kernel_table.h): chosen once, at the
/// first use, from the sets the build holds (a native build: the one of its -march; a portable
/// build: sse4, avx2 and avx512) as the widest the CPU supports, or forced by the environment
/// variable ARBOR_ISA=sse4|avx2|avx512 (an unknown name, a set the build does not hold or one the
/// CPU lacks: std::runtime_error with a one-line message, at that use and every later one).
#include <string>
#include <string_view>
#include <vector>

namespace arbor::accel {

struct KernelTable;

/// The table of the set in use.
const KernelTable& kernels();

/// The choice kernels() makes, for ARBOR_ISA = `forced` (nullptr or "": not set): the set named, or
/// the widest this CPU supports; throws std::runtime_error as kernels() does.
const KernelTable& choose_kernels(const char* forced);

/// Its name: "avx512" (AVX-512 F/BW/DQ/VL: 16-wide nodes and packets), "avx2" (AVX2 + FMA: 8-wide)
/// or "sse4" (SSE4.2: 4-wide).
std::string_view kernel_set();

/// The sets this build holds, narrowest first.
std::vector<std::string_view> kernel_sets_built();

/// Whether this CPU can run the set `name` ("sse4", "avx2", "avx512"; false for another name).
bool cpu_supports_kernel_set(std::string_view name);

/// What the set in use lacks against the widest one (AVX-512), in words for `arbor info`; empty
/// for avx512.
std::string kernel_set_skipped();

}  // namespace arbor::accel
