#pragma once
/// The Python queries: arguments checked and converted with the GIL held (arrays.h, args.h), the
/// results allocated (or the caller's `out=` checked), then arbor's work with the GIL released
/// under the scene's shared lock. Results have the leading shape of the rays or points.
#include <pybind11/pybind11.h>

#include "py_scene.h"

namespace arbor::python {

namespace py = pybind11;

py::object intersect(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                     py::handle out, py::handle threads, py::handle normals);
py::object occluded(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                    py::handle out, py::handle threads);
py::tuple intersect_all(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                        py::handle max_hits, py::handle out, py::handle threads, py::handle normals);
py::object closest_point(const PyScene& s, py::handle points, py::handle max_distance, py::handle out,
                         py::handle threads);
/// inside and signed_distance decide inside by `method` ("parity" or "winding"); the winding
/// queries take exact= (bool) and beta= (a number > 1) as arbor::WindingOptions.
py::object inside(const PyScene& s, py::handle points, py::handle method, py::handle out, py::handle threads,
                  py::handle exact, py::handle beta);
py::object winding_number(const PyScene& s, py::handle points, py::handle out, py::handle threads, py::handle exact,
                          py::handle beta);
py::object signed_distance(const PyScene& s, py::handle points, py::handle method, py::handle out, py::handle threads,
                           py::handle exact, py::handle beta);

}  // namespace arbor::python
