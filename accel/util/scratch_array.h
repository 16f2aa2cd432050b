#pragma once
/// ScratchArray<T>: a build temporary of n elements, left uninitialized (no zeroing pass: the
/// caller writes every element before reading it). On Linux, arrays of 2 MiB and more are aligned
/// to 2 MiB and advised to use transparent huge pages, which cuts the page faults of a
/// multi-million-triangle build by ~500x (see perf/lbvh_bench.cpp).
#include "accel/util/prefault.h"

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <span>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace arbor::accel {

template <class T> class ScratchArray {
    static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);

public:
    ScratchArray() = default;
    /// Allocates n elements (throws std::bad_alloc when out of memory).
    explicit ScratchArray(std::size_t n) : size_(n) {
        if (n == 0) return;
        constexpr std::size_t huge = std::size_t(2) << 20;
        const std::size_t bytes = n * sizeof(T);
        void* p = nullptr;
        if (bytes >= huge) {
            p = std::aligned_alloc(huge, (bytes + huge - 1) / huge * huge);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
            if (p) madvise(p, bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
        } else {
            p = std::aligned_alloc(alignof(std::max_align_t), (bytes + alignof(std::max_align_t) - 1) /
                                                                 alignof(std::max_align_t) * alignof(std::max_align_t));
        }
        if (!p) throw std::bad_alloc();
        data_.reset(static_cast<T*>(p));
        prefault(p, bytes);
    }

    T& operator[](std::size_t i) { return data_.get()[i]; }
    const T& operator[](std::size_t i) const { return data_.get()[i]; }
    T* data() { return data_.get(); }
    const T* data() const { return data_.get(); }
    std::size_t size() const { return size_; }
    std::size_t bytes() const { return size_ * sizeof(T); }
    std::span<T> span() { return {data_.get(), size_}; }
    std::span<const T> span() const { return {data_.get(), size_}; }
    void reset() { data_.reset(), size_ = 0; }

private:
    struct Free {
        void operator()(T* p) const { std::free(p); }
    };
    std::unique_ptr<T, Free> data_;
    std::size_t size_ = 0;
};

}  // namespace arbor::accel
