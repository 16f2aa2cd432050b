#include "arrays.h"

#include <arbor/arbor.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace arbor::python {

namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

std::string shape_of(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_name(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

/// `obj` as a numpy array (anything numpy.asarray takes); TypeError naming `what` otherwise.
py::array as_array(py::handle obj, const char* what, const char* expected) {
    if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
    try {
        return numpy().attr("asarray")(obj);
    } catch (py::error_already_set&) {
        throw py::type_error(std::string(what) + ": expected " + expected + ", got " +
                             py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>() +
                             " that numpy cannot make an array of");
    }
}

bool is_native_float32(const py::array& a) {
    const py::dtype d = a.dtype();
    return d.kind() == 'f' && d.itemsize() == 4 && d.byteorder() != '>';
}

/// A float32 copy of a real-valued array; TypeError for other kinds (bool, complex, text, objects).
py::array float32_copy(const py::array& a, const char* what, const char* expected) {
    const char k = a.dtype().kind();
    if (k != 'f' && k != 'i' && k != 'u')
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    return numpy().attr("ascontiguousarray")(a, py::arg("dtype") = "float32");
}

}  // namespace

Rows3 rows3(py::handle obj, const char* what) {
    constexpr const char* expected = "a float32 array of shape (N, 3)";
    py::array a = as_array(obj, what, expected);
    const char k = a.dtype().kind();
    if (k != 'f' && k != 'i' && k != 'u')
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error(std::string(what) + ": expected shape (N, 3), got " + shape_of(a));
    // In place: float32 with x, y, z next to each other and rows at a non-negative stride.
    if (!(is_native_float32(a) && a.strides(1) == 4 && a.strides(0) >= 0)) a = float32_copy(a, what, expected);
    Rows3 r;
    r.count = std::size_t(a.shape(0));
    r.stride = std::size_t(a.strides(0));
    r.data = static_cast<const float*>(a.data());
    r.keep = std::move(a);
    return r;
}

float number(py::handle obj, const char* what) {
    if (py::isinstance<py::bool_>(obj) || !(py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj) ||
                                            py::hasattr(obj, "__float__")))
        throw py::type_error(std::string(what) + ": expected a number, got " +
                             py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>());
    return float(obj.cast<double>());
}

PerRay per_ray(py::handle obj, const char* what, std::size_t n) {
    PerRay r;
    const bool is_array = py::isinstance<py::array>(obj) || py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj);
    if (!is_array || (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() == 0)) {
        // (A 0-d array's item() is a new object: held here, not in the borrowed handle.)
        const py::object scalar = py::isinstance<py::array>(obj) ? py::reinterpret_borrow<py::array>(obj).attr("item")()
                                                                 : py::reinterpret_borrow<py::object>(obj);
        r.value = number(scalar, what);
        return r;
    }
    constexpr const char* expected = "a number or a float32 array of shape (N,)";
    py::array a = as_array(obj, what, expected);
    const char k = a.dtype().kind();
    if (k != 'f' && k != 'i' && k != 'u')
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw py::value_error(std::string(what) + ": expected a number or shape (" + std::to_string(n) + ",) (one per ray), got " +
                              shape_of(a));
    if (!(is_native_float32(a) && a.strides(0) >= 0)) a = float32_copy(a, what, expected);
    r.data = static_cast<const float*>(a.data());
    r.stride = std::size_t(a.strides(0));
    r.keep = std::move(a);
    return r;
}

std::vector<std::uint32_t> faces(py::handle obj, std::size_t vertices) {
    constexpr const char* expected = "an integer array of shape (F, 3)";
    py::array a = as_array(obj, "faces", expected);
    if (a.size() == 0 && (a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 3))) return {};  // no faces ([] is float64)
    const char k = a.dtype().kind();
    if (k != 'i' && k != 'u') throw py::type_error(std::string("faces: expected ") + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("faces: expected shape (F, 3), got " + shape_of(a));
    const bool is_signed = k == 'i';
    const py::array wide = numpy().attr("ascontiguousarray")(a, py::arg("dtype") = is_signed ? "int64" : "uint64");
    const std::size_t n = std::size_t(a.shape(0)) * 3;
    std::vector<std::uint32_t> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool neg = is_signed && static_cast<const std::int64_t*>(wide.data())[i] < 0;
        const std::uint64_t v = is_signed ? std::uint64_t(static_cast<const std::int64_t*>(wide.data())[i])
                                          : static_cast<const std::uint64_t*>(wide.data())[i];
        if (neg || v >= vertices)
            throw py::value_error("faces: row " + std::to_string(i / 3) + " holds vertex index " +
                                  (neg ? std::to_string(static_cast<const std::int64_t*>(wide.data())[i]) : std::to_string(v)) +
                                  ", outside 0.." + (vertices ? std::to_string(vertices - 1) : std::string("(no vertices)")));
        out[i] = std::uint32_t(v);
    }
    return out;
}

void check_out_array(py::handle out, const py::dtype& dtype, const char* dtype_name_, std::size_t alignment, std::size_t n,
                std::initializer_list<py::handle> inputs) {
    const std::string expected = std::string("a numpy array of dtype ") + dtype_name_ + " and shape (" + std::to_string(n) + ",)";
    if (!py::isinstance<py::array>(out))
        throw py::type_error("out: expected " + expected + ", got " + py::str(py::type::handle_of(out).attr("__name__")).cast<std::string>());
    auto a = py::reinterpret_borrow<py::array>(out);
    if (!a.dtype().equal(dtype)) throw py::type_error("out: expected " + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n) throw py::value_error("out: expected " + expected + ", got shape " + shape_of(a));
    const int flags = py::detail::array_proxy(a.ptr())->flags;
    // (numpy calls a record of 4-byte fields aligned at any address: its own dtype is packed.)
    if (!(flags & py::detail::npy_api::NPY_ARRAY_C_CONTIGUOUS_) || !(flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_) ||
        reinterpret_cast<std::uintptr_t>(a.data()) % alignment != 0)
        throw py::value_error("out: expected a contiguous array at a multiple of " + std::to_string(alignment) +
                              " bytes (every record next to the last), got strides (" + std::to_string(a.strides(0)) + ",) at byte " +
                              std::to_string(reinterpret_cast<std::uintptr_t>(a.data()) % alignment) + " of " + std::to_string(alignment));
    if (!a.writeable()) throw py::value_error("out: the array is read-only");
    // The query reads its inputs while it writes: they must not be in the results' memory.
    const py::object may_share = numpy().attr("may_share_memory");
    for (const py::handle in : inputs)
        if (in && !in.is_none() && may_share(a, in).cast<bool>())
            throw py::value_error("out: shares memory with an input array (the query reads them while it writes out)");
}

py::dtype hit_dtype() {
    static_assert(sizeof(Hit) == 20 && offsetof(Hit, geom) == 4 && offsetof(Hit, prim) == 8 && offsetof(Hit, u) == 12 &&
                  offsetof(Hit, v) == 16);
    py::list fields;
    for (const char* f : {"t", "geom", "prim", "u", "v"})
        fields.append(py::make_tuple(f, std::string(f) == "geom" || std::string(f) == "prim" ? "<u4" : "<f4"));
    return py::dtype::from_args(fields);
}

py::dtype point_dtype() {
    static_assert(sizeof(ClosestPoint) == 32 && offsetof(ClosestPoint, geom) == 4 && offsetof(ClosestPoint, prim) == 8 &&
                  offsetof(ClosestPoint, point) == 12 && offsetof(ClosestPoint, u) == 24 && offsetof(ClosestPoint, v) == 28);
    py::list fields;
    fields.append(py::make_tuple("distance", "<f4"));
    fields.append(py::make_tuple("geom", "<u4"));
    fields.append(py::make_tuple("prim", "<u4"));
    fields.append(py::make_tuple("point", "<f4", py::make_tuple(3)));
    fields.append(py::make_tuple("u", "<f4"));
    fields.append(py::make_tuple("v", "<f4"));
    return py::dtype::from_args(fields);
}

}  // namespace arbor::python
