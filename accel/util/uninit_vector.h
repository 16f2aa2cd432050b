#pragma once
/// UninitVector<T>: std::vector for the big arrays of a traversal layout, whose allocator
/// default-initializes on resize() and emplace_back() instead of value-initializing, so trivial
/// elements get no zeroing pass before the layout builder writes every one of them.
///
/// (Their big arrays are advised to use transparent huge pages by prefault() when resized with
/// resize_prefaulted. Advising every array measured 2.5x slower for the 16-wide layout of a
/// 2.5M-triangle scene, 950-1050 ms against 375-390 ms: with THP defrag = madvise the first touch
/// of an advised region can wait for compaction. Advising the big arrays only made whole builds in
/// a fresh process 30-40% cheaper in CPU time.)
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace arbor::accel {

template <class T> struct DefaultInitAllocator : std::allocator<T> {
    using value_type = T;
    template <class U> struct rebind {
        using other = DefaultInitAllocator<U>;
    };

    DefaultInitAllocator() = default;
    template <class U> DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    /// resize(n) / emplace_back(): default-initialized (no zeroing of trivial types).
    template <class U> void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) { ::new (static_cast<void*>(p)) U; }
    template <class U, class... A> void construct(U* p, A&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(args)...);
    }
};

template <class T> using UninitVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace arbor::accel
