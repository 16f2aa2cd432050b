// The choice of the kernel set (kernel_set.h), and the entries of kernel_entries.h, which go to
// the set in use.
#include "accel/dispatch/kernel_set.h"

#include "accel/dispatch/kernel_table.h"
#include "accel/dispatch/kernel_entries.h"

#include <cstdlib>
#include <stdexcept>

namespace arbor::accel {
namespace {

/// The sets of this build, narrowest first (ARBOR_PORTABLE_BUILD: set by cmake on this file only).
/// A native build's one set is the one its -march made, which the CPU is not asked about (as before
/// there was a choice: -march=native is this CPU, and another -march is the builder's word).
#ifdef ARBOR_PORTABLE_BUILD
constexpr bool check_cpu = true;
std::vector<const KernelTable*> built() { return {arbor_kernels_sse4(), arbor_kernels_avx2(), arbor_kernels_avx512()}; }
#else
constexpr bool check_cpu = false;
std::vector<const KernelTable*> built() { return {arbor_kernels_native()}; }
#endif

std::string names(const std::vector<const KernelTable*>& sets) {
    std::string s;
    for (const KernelTable* t : sets) s += (s.empty() ? "" : ", ") + std::string(t->name);
    return s;
}

}  // namespace

const KernelTable& choose_kernels(const char* forced) {
    const std::vector<const KernelTable*> sets = built();
    if (forced == nullptr || *forced == '\0') {
        for (auto it = sets.rbegin(); it != sets.rend(); ++it)
            if (!check_cpu || cpu_supports_kernel_set((*it)->name)) return **it;
        throw std::runtime_error("this CPU supports none of this build's SIMD kernel sets (" + names(sets) +
                                 "; the portable build needs SSE4.2)");
    }
    const std::string want = forced;
    if (want != "sse4" && want != "avx2" && want != "avx512")
        throw std::runtime_error("ARBOR_ISA=" + want + ": unknown SIMD kernel set (expected sse4, avx2 or avx512)");
    for (const KernelTable* t : sets)
        if (want == t->name) {
            if (check_cpu && !cpu_supports_kernel_set(want))
                throw std::runtime_error("ARBOR_ISA=" + want + ": this CPU does not support the " + want + " kernel set");
            return *t;
        }
    throw std::runtime_error("ARBOR_ISA=" + want + ": this build holds only the " + names(sets) +
                             " kernel set (the one of its -march; configure with -DARBOR_PORTABLE=ON for sse4, avx2 and avx512)");
}

bool cpu_supports_kernel_set(std::string_view name) {
    __builtin_cpu_init();
    // The features -march=x86-64-v2, -v3 and -v4 let the compiler use (those __builtin_cpu_supports
    // knows in GCC 12 and clang 14; it checks the OS's register state for AVX too).
    const bool v2 = __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("popcnt");
    const bool v3 = v2 && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                    __builtin_cpu_supports("bmi2");
    const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                    __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
                    __builtin_cpu_supports("avx512cd");
    if (name == "sse4") return v2;
    if (name == "avx2") return v3;
    if (name == "avx512") return v4;
    return false;
}

const KernelTable& kernels() {
    static const KernelTable& chosen = choose_kernels(std::getenv("ARBOR_ISA"));
    return chosen;
}

std::string_view kernel_set() { return kernels().name; }

std::vector<std::string_view> kernel_sets_built() {
    std::vector<std::string_view> out;
    for (const KernelTable* t : built()) out.emplace_back(t->name);
    return out;
}

std::string kernel_set_skipped() {
    const std::string_view set = kernel_set();
    if (set == "sse4") return "no 8- or 16-wide BVH nodes, kd-tree blocks or packets (4 wide)";
    if (set == "avx2") return "no 16-wide BVH nodes, kd-tree blocks or packets (8 wide)";
    return "";
}

std::uint32_t default_wide_width() { return kernels().default_wide_width(); }
bool wide_width_supported(std::uint32_t width) { return kernels().wide_width_supported(width); }
std::uint32_t wide_width_or_default(std::uint32_t width) {
    return wide_width_supported(width) ? width : default_wide_width();
}
std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms) {
    return kernels().make_wide_bvh_accel(kind, bvh, tris, cfg, build_ms);
}
std::uint32_t default_kd_block_width() { return kernels().default_kd_block_width(); }
std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms) {
    return kernels().make_kd_simd_accel(std::move(tree), cfg, build_ms);
}

}  // namespace arbor::accel
