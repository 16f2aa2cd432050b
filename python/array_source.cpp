#include "array_source.h"

#include "args.h"

namespace arbor::python {

namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

/// The one-line message of the Python exception being handled (then cleared).
std::string reason(py::error_already_set& e) {
    std::string s = py::str(e.value()).cast<std::string>();
    if (const auto nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
    return s;
}

}  // namespace

bool is_array_like(py::handle obj) {
    return py::isinstance<py::array>(obj) || py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj) ||
           py::hasattr(obj, "__dlpack__") || py::hasattr(obj, "__array_interface__") || py::hasattr(obj, "__array__") ||
           PyObject_CheckBuffer(obj.ptr());
}

py::array as_array(py::handle obj, const char* what, const std::string& expected) {
    if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
    const auto refuse = [&](const std::string& why) {
        return py::type_error(std::string(what) + ": expected " + expected + ", got " + type_name(obj) +
                              " that numpy cannot make an array of" + why);
    };
    if (py::hasattr(obj, "__dlpack__")) {
        // DLPack first: it reads a tensor in place where __array__ might copy it (or refuse, as
        // torch does for tensors that require grad).
        try {
            return numpy().attr("from_dlpack")(obj);
        } catch (py::error_already_set& e) {
            // Another way in, if the object has one; else numpy.asarray would only wrap the
            // object itself in an array of dtype object.
            const bool other = py::hasattr(obj, "__array__") || py::hasattr(obj, "__array_interface__") ||
                               PyObject_CheckBuffer(obj.ptr());
            if (!other) throw refuse(" (numpy.from_dlpack: " + reason(e) + ")");
        }
    }
    try {
        return numpy().attr("asarray")(obj);
    } catch (py::error_already_set&) {
        throw refuse("");
    }
}

}  // namespace arbor::python
