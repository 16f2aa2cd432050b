#include "args.h"

#include <climits>

namespace arbor::python {

std::string type_name(py::handle obj) { return py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>(); }

long long count_arg(py::handle obj, const char* what, const char* expected, long long most) {
    const bool numpy_bool = py::hasattr(obj, "dtype") && py::str(obj.attr("dtype")).cast<std::string>() == "bool";
    if (PyBool_Check(obj.ptr()) || numpy_bool || !PyIndex_Check(obj.ptr()))
        throw py::type_error(std::string(what) + ": expected " + expected + ", got " + type_name(obj));
    const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr()));
    if (!index) {  // e.g. a numpy array of more than one int
        PyErr_Clear();
        throw py::type_error(std::string(what) + ": expected " + expected + ", got " + type_name(obj));
    }
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    if (overflow < 0 || (overflow == 0 && v < 0))
        throw py::value_error(std::string(what) + ": expected " + expected + ", got " +
                              py::str(index).cast<std::string>());
    return overflow > 0 || v > most ? most : v;
}

int threads_arg(py::handle obj, const char* meaning) {
    const std::string expected = std::string("an int >= 0 (0 = ") + meaning + ")";
    return int(count_arg(obj, "threads", expected.c_str(), INT_MAX));
}

std::string str_arg(py::handle obj, const char* what, const char* expected) {
    if (!py::isinstance<py::str>(obj))
        throw py::type_error(std::string(what) + ": expected a str (" + expected + "), got " + type_name(obj));
    return obj.cast<std::string>();
}

bool bool_arg(py::handle obj, const char* what) {
    if (PyBool_Check(obj.ptr())) return obj.ptr() == Py_True;
    if (py::isinstance(obj, py::module_::import("numpy").attr("bool_"))) return obj.cast<bool>();
    throw py::type_error(std::string(what) + ": expected a bool, got " + type_name(obj));
}

}  // namespace arbor::python
