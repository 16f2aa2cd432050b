#pragma once
/// Scene.winding_number, Scene.inside(points, method=...), Scene.signed_distance and Scene.closed
/// (../shared/spec/python.md, "Added in 0.2"), added to the Scene class from their own file.
#include <arbor/arbor.h>
#include <pybind11/pybind11.h>

#include <functional>

namespace arbor::python {

namespace py = pybind11;

/// Work on a scene: called with the arbor::Scene of a Python Scene object.
using SceneWork = std::function<void(const arbor::Scene&)>;
/// How the module runs work on the Scene object `self`: with the GIL released, under the scene's
/// shared (query) lock.
using SceneRunner = std::function<void(py::handle self, const SceneWork& work)>;

/// Adds the methods to `scene_class` (the module's Scene). `inside` is added as an overload after
/// the module's own inside(points): a call that passes `method` reaches this one.
void add_winding(py::object scene_class, SceneRunner run);

}  // namespace arbor::python
