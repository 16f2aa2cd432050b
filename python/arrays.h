#pragma once
/// Python arguments to arbor's arrays: arrays from anywhere (array_source.h) checked for dtype and
/// shape, with messages that name the argument and say what was expected. float32 rows whose
/// three coordinates are contiguous are read in place (any row stride, even 0 for a broadcast);
/// anything else a user would expect to work (float64, integers, a transposed or reversed array)
/// is converted to a float32 copy; the rest raises TypeError or ValueError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace arbor::python {

namespace py = pybind11;

/// An array shape; the leading shape of (..., 3) coordinates is the shape of the results.
using Shape = std::vector<py::ssize_t>;
/// "(4,)", "(2, 3)", "()".
std::string shape_str(const Shape& s);
py::ssize_t size_of(const Shape& s);

/// Rows of 3 float32 read while the GIL is released: `keep` owns (or borrows) the memory.
struct Rows3 {
    py::array keep;
    const float* data = nullptr;
    std::size_t count = 0;
    std::size_t stride = 12;  ///< bytes between rows
};

/// Mesh vertices: exactly (N, 3); `what` names the argument in errors.
Rows3 rows3(py::handle obj, const char* what);

/// `obj` as coordinates of shape (..., 3) of a real dtype, not yet converted ("origins", "points", ...).
py::array coords(py::handle obj, const char* what);
/// The shape of coordinates without their last axis.
Shape leading(const py::array& coords);
/// The leading shape of rays whose origins and directions have leading shapes `o` and `d`: numpy's
/// broadcasting (the same shape, or one row for all); ValueError naming directions otherwise.
Shape broadcast_rays(const Shape& o, const Shape& d);
/// coords(...) read as the size_of(shape) rows of a result of leading shape `shape`: in place when
/// the layout allows (one row for all: stride 0), else a float32 copy.
Rows3 rows_for(const py::array& coords, const Shape& shape);

/// A number or one float32 per result (tnear, tfar, max_distance): `value` when data is null.
struct PerValue {
    py::array keep;
    const float* data = nullptr;
    std::size_t stride = 4;
    float value = 0.0f;
};
/// `obj` as a number, or an array of exactly `shape` (one per `each`: "ray", "point"); a size-1
/// array for many results is an error, not a number.
PerValue per_value(py::handle obj, const char* what, const Shape& shape, const char* each);

/// A number (float) argument; TypeError naming it otherwise.
float number(py::handle obj, const char* what);

/// faces as 3 uint32 indices per row, each checked against `vertices` (ValueError naming the row).
std::vector<std::uint32_t> faces(py::handle obj, std::size_t vertices);

/// A caller's result array (`out=`, named `what` in errors): a writeable, C-contiguous array of
/// `shape` and `dtype` (named `dtype_name` in errors) at a multiple of `alignment` bytes, that shares
/// no memory with `inputs` (the arrays the query reads); TypeError for another type or dtype,
/// ValueError for another shape or layout.
void check_out_array(py::handle out, const char* what, const py::dtype& dtype, const char* dtype_name,
                     std::size_t alignment, const Shape& shape, std::initializer_list<py::handle> inputs);

/// The numpy dtypes of the results (python.md): hits, hits with normals, closest points; with
/// `inst`, the same with the field inst (scenes that hold instances). Each lies over arbor's
/// record (24 bytes a hit, 36 a closest point), so arbor writes them in place.
py::dtype hit_dtype(bool inst = false);
py::dtype hit_normal_dtype(bool inst = false);
py::dtype point_dtype(bool inst = false);

}  // namespace arbor::python
