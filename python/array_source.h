#pragma once
/// Any array a caller passes, as a numpy array, without copying when its layout allows: numpy
/// arrays as they are; objects exposing DLPack (`__dlpack__`, e.g. a torch CPU tensor) through
/// numpy.from_dlpack; anything else numpy.asarray takes (the buffer protocol, `__array_interface__`,
/// `__array__`, nested lists).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace arbor::python {

namespace py = pybind11;

/// `obj` as a numpy array; TypeError naming `what` (and saying `expected`) when numpy cannot make one.
py::array as_array(py::handle obj, const char* what, const std::string& expected);

/// Whether `obj` is array-like (so a size-1 one is not taken for a number): a numpy array, a list
/// or tuple, or an object exposing DLPack, `__array_interface__`, `__array__` or the buffer protocol.
bool is_array_like(py::handle obj);

}  // namespace arbor::python
