#pragma once
/// The Python Scene: an arbor::Scene and the lock that lets queries from several Python threads
/// share it while add_mesh() and build() wait for them (and they, once a writer waits, for it).
#include <arbor/arbor.h>
#include <pybind11/pybind11.h>

#include <mutex>
#include <shared_mutex>

#include "writer_first_mutex.h"

namespace arbor::python {

struct PyScene {
    arbor::Scene scene;
    mutable WriterFirstMutex mutex;
};

/// Runs `f` on the scene with the GIL released: shared (queries, properties) or exclusive
/// (changes). The lock is let go before the GIL is taken back, so no thread ever holds the lock
/// while it waits for the GIL.
template <bool Exclusive, class F>
void run(const PyScene& s, F&& f) {
    pybind11::gil_scoped_release nogil;
    if constexpr (Exclusive) {
        const std::unique_lock lock(s.mutex);
        f();
    } else {
        const std::shared_lock lock(s.mutex);
        f();
    }
}

/// What `get(scene)` returns, read under the shared lock (the body of a read-only property).
template <class Get>
auto read(const PyScene& s, Get&& get) {
    decltype(get(s.scene)) value{};
    run<false>(s, [&] { value = get(s.scene); });
    return value;
}

}  // namespace arbor::python
