#pragma once
/// Scene.update_vertices and what it reports (update_action, update_reason), added to the Scene
/// class that module.cpp defines.
#include <pybind11/pybind11.h>

namespace arbor::python {

/// Adds the methods and properties to `m`'s Scene class (module.cpp defines it first).
void bind_update(pybind11::module_& m);

}  // namespace arbor::python
