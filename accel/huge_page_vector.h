#pragma once
/// HugePageVector<T>: std::vector for the big arrays of a traversal layout. Its allocator (a) puts
/// allocations of 2 MiB and more on 2 MiB boundaries advised to use transparent huge pages, as
/// ScratchArray does for build temporaries: the first touch of a 100 MB triangle-block array then
/// takes ~50 page faults instead of ~25,000 (under KVM each fault is an exit: on a 2.5M-triangle
/// build the faults of the wide layout were 11% of the build time, perf record); and (b)
/// default-initializes on resize() instead of value-initializing, so trivial elements get no
/// zeroing pass: the layout builders write every element they resize to.
#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace arbor::accel {

template <class T> struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() = default;
    template <class U> HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        constexpr std::size_t huge = std::size_t(2) << 20;
        constexpr std::size_t align = alignof(T) > alignof(std::max_align_t) ? alignof(T) : alignof(std::max_align_t);
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        const std::size_t bytes = n * sizeof(T);
        void* p = nullptr;
        if (bytes >= huge) {
            p = std::aligned_alloc(huge, (bytes + huge - 1) / huge * huge);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
            if (p) madvise(p, bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
        } else {
            p = std::aligned_alloc(align, (bytes + align - 1) / align * align);
        }
        if (!p) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t) noexcept { std::free(p); }

    /// resize(n) / emplace_back(): default-initialized (no zeroing of trivial types).
    template <class U> void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) { ::new (static_cast<void*>(p)) U; }
    template <class U, class... A> void construct(U* p, A&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(args)...);
    }

    template <class U> bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

template <class T> using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace arbor::accel
