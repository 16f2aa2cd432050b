#pragma once
/// The Python Scene's instances: add_instance, set_transform and the instances property.
#include <pybind11/pybind11.h>

#include "py_scene.h"

namespace arbor::python {

/// Adds add_instance(geom, transform), set_transform(inst, transform) and `instances` to `cls`.
void def_instances(pybind11::class_<PyScene>& cls);

}  // namespace arbor::python
