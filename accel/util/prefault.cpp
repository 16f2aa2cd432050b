#include "accel/util/prefault.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace arbor::accel {

void prefault(void* data, std::size_t bytes) {
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
    constexpr int MADV_POPULATE_WRITE = 23;  // Linux 5.14; older kernels answer EINVAL: nothing happens
#endif
    constexpr std::size_t min_bytes = std::size_t(1) << 20, chunk = std::size_t(4) << 20;
    if (bytes < min_bytes) return;
    const auto page = std::uintptr_t(sysconf(_SC_PAGESIZE));
    const auto begin = (std::uintptr_t(data) + page - 1) / page * page;
    const auto end = (std::uintptr_t(data) + bytes) / page * page;
    if (end <= begin) return;
    // Transparent huge pages for the 2 MiB-aligned part (THP "madvise" mode): one fault maps 2 MiB
    // instead of 4 KiB. In the test machine's VM a 4 KiB fault costs ~8-16 us of CPU; 256 MiB took
    // 250-520 ms CPU as huge pages, 610-670 ms populated as 4 KiB pages, 1.1 s faulted one by one.
    // Embree's allocator asks for huge pages too.
    constexpr std::uintptr_t huge = std::uintptr_t(2) << 20;
    const std::uintptr_t hb = (begin + huge - 1) / huge * huge, he = end / huge * huge;
    if (he > hb) madvise(reinterpret_cast<void*>(hb), he - hb, MADV_HUGEPAGE);  // advice: errors change nothing
    tbb::parallel_for(tbb::blocked_range<std::uintptr_t>(0, (end - begin + chunk - 1) / chunk, 1),
                      [&](const tbb::blocked_range<std::uintptr_t>& r) {
                          for (std::uintptr_t c = r.begin(); c != r.end(); ++c) {
                              const std::uintptr_t a = begin + c * chunk, b = std::min(end, a + chunk);
                              madvise(reinterpret_cast<void*>(a), b - a, MADV_POPULATE_WRITE);  // advice: errors change nothing
                          }
                      });
#else
    (void)data, (void)bytes;
#endif
}

}  // namespace arbor::accel
