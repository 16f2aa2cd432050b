#pragma once
/// Python arguments to arbor's arrays: numpy arrays (or anything numpy.asarray takes) checked for
/// dtype and shape, with messages that name the argument and say what was expected. float32 rows
/// whose three coordinates are contiguous are read in place (any row stride, even 0 for a
/// broadcast); anything else a user would expect to work (float64, integers, a transposed or
/// reversed array) is converted to a float32 copy; the rest raises TypeError or ValueError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace arbor::python {

namespace py = pybind11;

/// An (N, 3) float32 view: `keep` owns (or borrows) the memory read while the GIL is released.
struct Rows3 {
    py::array keep;
    const float* data = nullptr;
    std::size_t count = 0;
    std::size_t stride = 12;  ///< bytes between rows
};

/// `obj` as (N, 3) coordinates; `what` names it in errors ("origins", "points", ...).
Rows3 rows3(py::handle obj, const char* what);

/// tnear / tfar: a number (`value`, data null) or an (N,) array read in place when float32.
struct PerRay {
    py::array keep;
    const float* data = nullptr;
    std::size_t stride = 4;
    float value = 0.0f;
};
PerRay per_ray(py::handle obj, const char* what, std::size_t n);

/// A number (float) argument; TypeError naming it otherwise.
float number(py::handle obj, const char* what);

/// faces as 3 uint32 indices per row, each checked against `vertices` (ValueError naming the row).
std::vector<std::uint32_t> faces(py::handle obj, std::size_t vertices);

/// A caller's result array (`out=`): a writeable, C-contiguous (N,) array of `dtype` (named
/// `dtype_name` in errors) at a multiple of `alignment` bytes, that
/// shares no memory with `inputs` (the arrays the query reads); TypeError / ValueError naming
/// `out` otherwise.
void check_out_array(py::handle out, const py::dtype& dtype, const char* dtype_name, std::size_t alignment, std::size_t n,
                std::initializer_list<py::handle> inputs);

/// The numpy dtypes of the results (python.md): hits and closest points.
py::dtype hit_dtype();
py::dtype point_dtype();

}  // namespace arbor::python
