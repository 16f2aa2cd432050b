#pragma once
/// Python scalar arguments (ints, strings, bools) checked by hand, so that a wrong one raises a
/// one-line TypeError or ValueError naming it rather than pybind11's list of signatures.
#include <pybind11/pybind11.h>

#include <string>

namespace arbor::python {

namespace py = pybind11;

/// The name of obj's type ("float", "NoneType", ...), for messages.
std::string type_name(py::handle obj);

/// An int (a Python int or anything with __index__, e.g. numpy.int64; not a bool) >= 0; TypeError
/// or ValueError naming `what`, whose message says what was expected (`expected`, e.g. "an int >= 0
/// (0 = all cores)"). Values beyond `most` are taken as `most`.
long long count_arg(py::handle obj, const char* what, const char* expected, long long most);

/// `threads=` of a query or build: an int >= 0, capped at INT_MAX (arbor caps it at the cores).
int threads_arg(py::handle obj, const char* meaning);

/// A str (TypeError naming `what` otherwise; `expected` says which strings are meant).
std::string str_arg(py::handle obj, const char* what, const char* expected);

/// A bool (Python's or numpy's); TypeError naming `what` otherwise.
bool bool_arg(py::handle obj, const char* what);

}  // namespace arbor::python
