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
