#include "arrays.h"

#include <arbor/arbor.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "args.h"
#include "array_source.h"

namespace arbor::python {

namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

Shape shape_of(const py::array& a) { return Shape(a.shape(), a.shape() + a.ndim()); }

std::string dtype_name(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

bool is_real(const py::array& a) {
    const char k = a.dtype().kind();
    return k == 'f' || k == 'i' || k == 'u';
}

bool is_native_float32(const py::array& a) {
    const py::dtype d = a.dtype();
    return d.kind() == 'f' && d.itemsize() == 4 && d.byteorder() != '>';
}

/// A float32 copy of a real-valued array.
py::array float32_copy(const py::array& a) {
    return numpy().attr("ascontiguousarray")(a, py::arg("dtype") = "float32");
}

py::tuple as_tuple(const Shape& s) {
    py::tuple t(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) t[i] = py::int_(s[i]);
    return t;
}

/// (N, 3) rows as Rows3: read in place when float32 with x, y, z next to each other and rows at a
/// non-negative stride, else from a float32 copy.
Rows3 rows_of(py::array a, std::size_t count, bool one_for_all) {
    if (!(is_native_float32(a) && a.strides(1) == 4 && a.strides(0) >= 0)) a = float32_copy(a);
    Rows3 r;
    r.count = count;
    r.stride = one_for_all ? 0 : std::size_t(a.strides(0));
    r.data = static_cast<const float*>(a.data());
    r.keep = std::move(a);
    return r;
}

}  // namespace

std::string shape_str(const Shape& s) {
    std::string out = "(";
    for (std::size_t i = 0; i < s.size(); ++i) out += (i ? ", " : "") + std::to_string(s[i]);
    return out + (s.size() == 1 ? ",)" : ")");
}

py::ssize_t size_of(const Shape& s) {
    py::ssize_t n = 1;
    for (const py::ssize_t k : s) n *= k;
    return n;
}

Rows3 rows3(py::handle obj, const char* what) {
    constexpr const char* expected = "a float32 array of shape (N, 3)";
    const py::array a = as_array(obj, what, expected);
    if (!is_real(a))
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error(std::string(what) + ": expected shape (N, 3), got " + shape_str(shape_of(a)));
    return rows_of(a, std::size_t(a.shape(0)), false);
}

py::array coords(py::handle obj, const char* what) {
    constexpr const char* expected = "a float32 array of shape (N, 3) or (..., 3)";
    const py::array a = as_array(obj, what, expected);
    if (!is_real(a))
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
        throw py::value_error(std::string(what) + ": expected shape (N, 3) or (..., 3), got " + shape_str(shape_of(a)));
    return a;
}

Shape leading(const py::array& coords) { return Shape(coords.shape(), coords.shape() + coords.ndim() - 1); }

Shape broadcast_rays(const Shape& o, const Shape& d) {
    Shape s(std::max(o.size(), d.size()));
    for (std::size_t i = 0; i < s.size(); ++i) {
        // Axes counted from the last, as numpy broadcasts them.
        const py::ssize_t a = i < o.size() ? o[o.size() - 1 - i] : 1;
        const py::ssize_t b = i < d.size() ? d[d.size() - 1 - i] : 1;
        if (a != b && a != 1 && b != 1) {
            if (o.size() == 1 && d.size() == 1)
                throw py::value_error("directions: expected " + std::to_string(o[0]) +
                                      " rows like origins (or 1), got " + std::to_string(d[0]));
            throw py::value_error("directions: expected a shape that broadcasts with origins' " + shape_str(o) +
                                  " (the same, or one row for all), got " + shape_str(d));
        }
        s[s.size() - 1 - i] = a == 1 ? b : a;
    }
    return s;
}

Rows3 rows_for(const py::array& a, const Shape& shape) {
    const Shape lead = leading(a);
    const auto n = std::size_t(size_of(shape));
    if (size_of(lead) == 1 && n != 1) return rows_of(a.attr("reshape")(1, 3), n, true);
    // numpy's reshape is a view whenever the rows allow one (e.g. an (H, W, 3) array in C order).
    if (lead == shape) return rows_of(a.attr("reshape")(-1, 3), n, false);
    Shape full = shape;
    full.push_back(3);
    return rows_of(numpy().attr("broadcast_to")(a, as_tuple(full)).attr("reshape")(-1, 3), n, false);
}

float number(py::handle obj, const char* what) {
    if (py::isinstance<py::bool_>(obj) || !(py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj) ||
                                            py::hasattr(obj, "__float__")))
        throw py::type_error(std::string(what) + ": expected a number, got " + type_name(obj));
    return float(obj.cast<double>());
}

PerValue per_value(py::handle obj, const char* what, const Shape& shape, const char* each) {
    PerValue r;
    const std::string expected = "a number or a float32 array of shape " + shape_str(shape) + " (one per " + each + ")";
    if (!is_array_like(obj)) {
        r.value = number(obj, what);
        return r;
    }
    py::array a = as_array(obj, what, expected);
    if (a.ndim() == 0) {
        // (A 0-d array's item() is a new object: held here, not in the borrowed handle.)
        const py::object scalar = a.attr("item")();
        r.value = number(scalar, what);
        return r;
    }
    if (!is_real(a))
        throw py::type_error(std::string(what) + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (shape_of(a) != shape)
        throw py::value_error(std::string(what) + ": expected a number or shape " + shape_str(shape) + " (one per " +
                              each + "), got " + shape_str(shape_of(a)));
    a = a.attr("reshape")(-1);
    if (!(is_native_float32(a) && a.strides(0) >= 0)) a = float32_copy(a);
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
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error("faces: expected shape (F, 3), got " + shape_str(shape_of(a)));
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

void check_out_array(py::handle out, const char* what, const py::dtype& dtype, const char* dtype_name_,
                     std::size_t alignment, const Shape& shape, std::initializer_list<py::handle> inputs) {
    const std::string w = what;
    const std::string expected =
        std::string("a numpy array of dtype ") + dtype_name_ + " and shape " + shape_str(shape);
    if (!py::isinstance<py::array>(out)) throw py::type_error(w + ": expected " + expected + ", got " + type_name(out));
    auto a = py::reinterpret_borrow<py::array>(out);
    if (!a.dtype().equal(dtype)) throw py::type_error(w + ": expected " + expected + ", got dtype " + dtype_name(a));
    if (shape_of(a) != shape)
        throw py::value_error(w + ": expected " + expected + ", got shape " + shape_str(shape_of(a)));
    const int flags = py::detail::array_proxy(a.ptr())->flags;
    // (numpy calls a record of 4-byte fields aligned at any address: its own dtype is packed.)
    const auto misalign = reinterpret_cast<std::uintptr_t>(a.data()) % alignment;
    if (!(flags & py::detail::npy_api::NPY_ARRAY_C_CONTIGUOUS_) || !(flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_) ||
        misalign != 0) {
        std::string strides;
        for (py::ssize_t i = 0; i < a.ndim(); ++i) strides += (i ? ", " : "") + std::to_string(a.strides(i));
        throw py::value_error(w + ": expected a contiguous array at a multiple of " + std::to_string(alignment) +
                              " bytes (every record next to the last), got strides (" + strides +
                              (a.ndim() == 1 ? ",)" : ")") + " at byte " + std::to_string(misalign) + " of " +
                              std::to_string(alignment));
    }
    if (!a.writeable()) throw py::value_error(w + ": the array is read-only");
    // The query reads its inputs while it writes: they must not be in the results' memory.
    const py::object may_share = numpy().attr("may_share_memory");
    for (const py::handle in : inputs)
        if (in && !in.is_none() && may_share(a, in).cast<bool>())
            throw py::value_error(w + ": shares memory with an input array (the query reads them while it writes " + w +
                                  ")");
}

namespace {

/// A record dtype of `fields` (name, format, shape; the shape empty for a scalar) at their C++
/// offsets, `itemsize` bytes a record: the fields an array shows, laid over arbor's records, which
/// may hold more (the inst field of a scene without instances is padding).
py::dtype record_dtype(std::initializer_list<std::tuple<const char*, const char*, int, std::size_t>> fields,
                       std::size_t itemsize) {
    py::list names, formats, offsets;
    for (const auto& [name, format, count, offset] : fields) {
        names.append(name);
        formats.append(count > 1 ? py::str(std::to_string(count) + format) : py::str(format));
        offsets.append(offset);
    }
    py::dict spec;
    spec["names"] = names, spec["formats"] = formats, spec["offsets"] = offsets, spec["itemsize"] = itemsize;
    return py::dtype::from_args(spec);
}

}  // namespace

static_assert(sizeof(Hit) == 24 && offsetof(Hit, geom) == 4 && offsetof(Hit, prim) == 8 && offsetof(Hit, u) == 12 &&
              offsetof(Hit, v) == 16 && offsetof(Hit, inst) == 20);
static_assert(sizeof(ClosestPoint) == 36 && offsetof(ClosestPoint, geom) == 4 && offsetof(ClosestPoint, prim) == 8 &&
              offsetof(ClosestPoint, point) == 12 && offsetof(ClosestPoint, u) == 24 && offsetof(ClosestPoint, v) == 28 &&
              offsetof(ClosestPoint, inst) == 32);

py::dtype hit_dtype(bool inst) {
    if (inst)
        return record_dtype({{"t", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8}, {"inst", "<u4", 1, 20},
                             {"u", "<f4", 1, 12}, {"v", "<f4", 1, 16}}, sizeof(Hit));
    return record_dtype({{"t", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8}, {"u", "<f4", 1, 12},
                         {"v", "<f4", 1, 16}}, sizeof(Hit));
}

py::dtype hit_normal_dtype(bool inst) {
    constexpr std::size_t n = sizeof(Hit);  // the normal follows the whole hit record
    if (inst)
        return record_dtype({{"t", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8}, {"inst", "<u4", 1, 20},
                             {"u", "<f4", 1, 12}, {"v", "<f4", 1, 16}, {"normal", "<f4", 3, n}}, n + 12);
    return record_dtype({{"t", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8}, {"u", "<f4", 1, 12},
                         {"v", "<f4", 1, 16}, {"normal", "<f4", 3, n}}, n + 12);
}

py::dtype point_dtype(bool inst) {
    if (inst)
        return record_dtype({{"distance", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8},
                             {"inst", "<u4", 1, 32}, {"point", "<f4", 3, 12}, {"u", "<f4", 1, 24}, {"v", "<f4", 1, 28}},
                            sizeof(ClosestPoint));
    return record_dtype({{"distance", "<f4", 1, 0}, {"geom", "<u4", 1, 4}, {"prim", "<u4", 1, 8},
                         {"point", "<f4", 3, 12}, {"u", "<f4", 1, 24}, {"v", "<f4", 1, 28}},
                        sizeof(ClosestPoint));
}

}  // namespace arbor::python
