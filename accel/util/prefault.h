#pragma once
/// prefault(): maps the pages of a freshly allocated array before a builder writes it. A first write
/// to an unmapped page costs a page fault each (~2 us per 4 KiB page on the 2-core test machine:
/// 0.5 ms per MB, a tenth of a 2.5M-triangle build); Linux's MADV_POPULATE_WRITE maps a whole range
/// in one call for ~0.3 ms per MB, and the range is split over TBB tasks. The range's 2 MiB-aligned
/// part is first advised to use transparent huge pages (one fault per 2 MiB: in a fresh process
/// most of a build's page faults). Only for arrays that are
/// written in full right after (it commits the memory); a no-op elsewhere and below 1 MiB.
#include <cstddef>

namespace arbor::accel {

void prefault(void* data, std::size_t bytes);

/// v.resize(n) with the new elements' pages mapped first (v: a vector of trivial elements).
template <class V> void resize_prefaulted(V& v, std::size_t n) {
    if (n > v.size()) {
        v.reserve(n);
        prefault(v.data() + v.size(), (n - v.size()) * sizeof(*v.data()));
    }
    v.resize(n);
}

}  // namespace arbor::accel
