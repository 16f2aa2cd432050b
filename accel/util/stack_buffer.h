#pragma once
/// StackBuffer: a traversal stack on the call stack when the tree is shallow enough, else on the heap
/// (no allocation per traced batch for the usual trees).
#include <array>
#include <cstddef>
#include <vector>

namespace arbor::accel {

template <class E, std::size_t Small> class StackBuffer {
public:
    explicit StackBuffer(std::size_t size) {
        if (size > Small) large_.resize(size);
    }
    E* data() { return large_.empty() ? small_.data() : large_.data(); }

private:
    std::array<E, Small> small_;
    std::vector<E> large_;
};

}  // namespace arbor::accel
