#include "queries.h"

#include <cstring>
#include <limits>
#include <string>

#include "args.h"
#include "arrays.h"

namespace arbor::python {

namespace {

/// The rays of a query: origins and directions of shapes that broadcast (one row of either for
/// every ray), tnear and tfar numbers or arrays of the rays' leading shape.
struct Rays {
    Rows3 org, dir;
    PerValue tnear, tfar;
    Shape shape;  ///< the leading shape of the rays, and of the results
    arbor::RayArrays view;
};

Rays rays(py::handle origins, py::handle directions, py::handle tnear, py::handle tfar) {
    Rays r;
    const py::array o = coords(origins, "origins");
    const py::array d = coords(directions, "directions");
    r.shape = broadcast_rays(leading(o), leading(d));
    r.org = rows_for(o, r.shape);
    r.dir = rows_for(d, r.shape);
    r.tnear = per_value(tnear, "tnear", r.shape, "ray");
    r.tfar = per_value(tfar, "tfar", r.shape, "ray");
    arbor::RayArrays& v = r.view;
    v.count = r.org.count;
    v.origins = r.org.data, v.origin_stride = r.org.stride;
    v.directions = r.dir.data, v.direction_stride = r.dir.stride;
    v.tnear = r.tnear.data, v.tnear_stride = r.tnear.stride, v.tnear_value = r.tnear.value;
    v.tfar = r.tfar.data, v.tfar_stride = r.tfar.stride, v.tfar_value = r.tfar.value;
    return r;
}

/// The array a query's results go to: a new array of `dtype` and `shape`, or the caller's `out`
/// once checked (arrays.h: check_out_array).
py::array result(py::handle out, const py::dtype& dtype, const char* dtype_name, std::size_t alignment,
                 const Shape& shape, std::initializer_list<py::handle> inputs) {
    if (out.is_none()) return py::array(dtype, shape);
    check_out_array(out, "out", dtype, dtype_name, alignment, shape, inputs);
    return py::reinterpret_borrow<py::array>(out);
}

arbor::PointArrays points_of(const Rows3& p) { return {p.count, p.data, p.stride}; }

arbor::QueryOptions options(py::handle threads) { return {threads_arg(threads, "the scene's threads")}; }

/// Records with a normal: 24-byte hits then 12 bytes of normal (hit_normal_dtype).
constexpr std::size_t normal_record = 36;
static_assert(sizeof(arbor::Hit) + 3 * sizeof(float) == normal_record);

/// Turns `n` packed hits at the start of `records` (as arbor wrote them) into records with their
/// normal. The hits move to their 32-byte places last first, so none is overwritten before it
/// moves (record i's place starts at or after the end of every hit before it); then the normals
/// are written into the gaps, in parallel.
void add_normals(const arbor::Scene& scene, unsigned char* records, std::size_t n, const arbor::QueryOptions& o) {
    for (std::size_t i = n; i-- > 0;)
        std::memmove(records + i * normal_record, records + i * sizeof(arbor::Hit), sizeof(arbor::Hit));
    scene.hit_normals(reinterpret_cast<const arbor::Hit*>(records), n, normal_record,
                      reinterpret_cast<float*>(records + sizeof(arbor::Hit)), normal_record, o);
}

/// Whether the scene holds instances (then its records show the field inst).
bool has_instances(const PyScene& s) {
    return read(s, [](const arbor::Scene& sc) { return sc.instances(); }) > 0;
}

py::dtype hits_dtype(bool normals, bool inst) { return normals ? hit_normal_dtype(inst) : hit_dtype(inst); }
const char* hits_dtype_name(bool normals, bool inst) {
    if (inst) return normals ? "arbor.hit_inst_normal_dtype" : "arbor.hit_inst_dtype";
    return normals ? "arbor.hit_normal_dtype" : "arbor.hit_dtype";
}

/// Points as coordinates of shape (..., 3) and the leading shape of the results.
struct Points {
    Shape shape;
    Rows3 rows;
};

Points points(py::handle obj) {
    const py::array p = coords(obj, "points");
    Points out;
    out.shape = leading(p);
    out.rows = rows_for(p, out.shape);
    return out;
}

/// method= of inside and signed_distance.
arbor::InsideMethod inside_method(py::handle obj) {
    const std::string m = str_arg(obj, "method", "\"parity\" or \"winding\"");
    if (m == "parity") return arbor::InsideMethod::parity;
    if (m == "winding") return arbor::InsideMethod::winding;
    throw py::value_error("method: expected \"parity\" or \"winding\", got " + py::repr(obj).cast<std::string>());
}

/// exact= and beta= of the winding-number queries (beta: a real number > 1, inf: exact).
arbor::WindingOptions winding_options(py::handle exact, py::handle beta) {
    arbor::WindingOptions w;
    w.exact = bool_arg(exact, "exact");
    // A number: Python's or numpy's (not a bool, not an array of several).
    bool number = !py::isinstance<py::bool_>(beta) && !py::isinstance<py::str>(beta) &&
                  !py::isinstance(beta, py::module_::import("numpy").attr("bool_")) && PyNumber_Check(beta.ptr());
    if (number) {
        try {
            w.beta = py::float_(py::reinterpret_borrow<py::object>(beta)).cast<double>();
        } catch (py::error_already_set&) {
            number = false;
        }
    }
    if (!number) throw py::type_error("beta: expected a number > 1 (inf: exact), got " + type_name(beta));
    if (!(w.beta > 1.0))
        throw py::value_error("beta: expected a number > 1 (inf: exact), got " + py::repr(beta).cast<std::string>());
    return w;
}

float value_at(const PerValue& v, std::size_t i) {
    float x;
    std::memcpy(&x, reinterpret_cast<const unsigned char*>(v.data) + i * v.stride, sizeof x);
    return x;
}

}  // namespace

py::object intersect(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                     py::handle out, py::handle threads, py::handle normals) {
    const arbor::QueryOptions o = options(threads);
    const bool with_normals = bool_arg(normals, "normals");
    const Rays r = rays(origins, directions, tnear, tfar);
    const bool inst = has_instances(s);
    py::array res = result(out, hits_dtype(with_normals, inst), hits_dtype_name(with_normals, inst), alignof(arbor::Hit), r.shape,
                           {origins, directions, tnear, tfar});
    auto* records = static_cast<unsigned char*>(res.mutable_data());
    run<false>(s, [&] {
        s.scene.intersect(r.view, reinterpret_cast<arbor::Hit*>(records), o);
        if (with_normals) add_normals(s.scene, records, r.view.count, o);
    });
    return std::move(res);
}

py::object occluded(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                    py::handle out, py::handle threads) {
    const arbor::QueryOptions o = options(threads);
    const Rays r = rays(origins, directions, tnear, tfar);
    py::array res =
        result(out, py::dtype::of<bool>(), "bool", alignof(bool), r.shape, {origins, directions, tnear, tfar});
    bool* occ = static_cast<bool*>(res.mutable_data());
    run<false>(s, [&] { s.scene.occluded(r.view, occ, o); });
    return std::move(res);
}

py::tuple intersect_all(const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
                        py::handle max_hits, py::handle out, py::handle threads, py::handle normals) {
    const arbor::QueryOptions o = options(threads);
    const bool with_normals = bool_arg(normals, "normals");
    const auto k = py::ssize_t(count_arg(max_hits, "max_hits", "an int >= 0", std::numeric_limits<py::ssize_t>::max()));
    const Rays r = rays(origins, directions, tnear, tfar);
    Shape rows = r.shape;
    rows.push_back(k);
    const bool inst = has_instances(s);
    py::array hits, counts;
    if (out.is_none()) {
        hits = py::array(hits_dtype(with_normals, inst), rows);
        counts = py::array(py::dtype::of<std::int32_t>(), r.shape);
    } else {
        if (!py::isinstance<py::tuple>(out) && !py::isinstance<py::list>(out))
            throw py::type_error("out: expected a tuple (hits, counts) of numpy arrays of shapes " + shape_str(rows) +
                                 " and " + shape_str(r.shape) + ", got " + type_name(out));
        if (py::len(out) != 2)
            throw py::value_error("out: expected a tuple (hits, counts) of two numpy arrays, got " +
                                  std::to_string(py::len(out)) + " items");
        const py::object h = out[py::int_(0)], c = out[py::int_(1)];
        check_out_array(h, "out[0]", hits_dtype(with_normals, inst), hits_dtype_name(with_normals, inst), alignof(arbor::Hit), rows,
                        {origins, directions, tnear, tfar});
        check_out_array(c, "out[1]", py::dtype::of<std::int32_t>(), "int32", alignof(std::int32_t), r.shape,
                        {origins, directions, tnear, tfar, h});
        hits = py::reinterpret_borrow<py::array>(h);
        counts = py::reinterpret_borrow<py::array>(c);
    }
    auto* records = static_cast<unsigned char*>(hits.mutable_data());
    auto* c = static_cast<std::int32_t*>(counts.mutable_data());
    run<false>(s, [&] {
        s.scene.intersect_all(r.view, std::size_t(k), reinterpret_cast<arbor::Hit*>(records), c, o);
        if (with_normals) add_normals(s.scene, records, r.view.count * std::size_t(k), o);
    });
    return py::make_tuple(hits, counts);
}

py::object closest_point(const PyScene& s, py::handle points_obj, py::handle max_distance, py::handle out,
                         py::handle threads) {
    const arbor::QueryOptions o = options(threads);
    const Points p = points(points_obj);
    const PerValue reach = per_value(max_distance, "max_distance", p.shape, "point");
    if (!reach.data && !(reach.value >= 0.0f))
        throw py::value_error("max_distance: expected a number >= 0 (inf: no limit)");
    if (reach.data)
        for (std::size_t i = 0; i < p.rows.count; ++i)
            if (!(value_at(reach, i) >= 0.0f))
                throw py::value_error("max_distance: expected numbers >= 0 (inf: no limit), got " +
                                      py::repr(py::float_(value_at(reach, i))).cast<std::string>() + " at flat index " +
                                      std::to_string(i));
    const bool inst = has_instances(s);
    py::array res = result(out, point_dtype(inst), inst ? "arbor.point_inst_dtype" : "arbor.point_dtype",
                           alignof(arbor::ClosestPoint), p.shape,
                           {points_obj, max_distance});
    auto* near = static_cast<arbor::ClosestPoint*>(res.mutable_data());
    const arbor::PointValues pv{reach.data, reach.stride, reach.value};
    run<false>(s, [&] { s.scene.closest_point(points_of(p.rows), pv, near, o); });
    return std::move(res);
}

/// The arguments inside and signed_distance share, read (and checked) in this order.
struct MethodArgs {
    arbor::QueryOptions o;
    arbor::InsideMethod m;
    arbor::WindingOptions w;
    Points p;
};

MethodArgs method_args(py::handle points_obj, py::handle method, py::handle threads, py::handle exact,
                       py::handle beta) {
    return {options(threads), inside_method(method), winding_options(exact, beta), points(points_obj)};
}

py::object inside(const PyScene& s, py::handle points_obj, py::handle method, py::handle out, py::handle threads,
                  py::handle exact, py::handle beta) {
    const MethodArgs a = method_args(points_obj, method, threads, exact, beta);
    py::array res = result(out, py::dtype::of<bool>(), "bool", alignof(bool), a.p.shape, {points_obj});
    bool* in = static_cast<bool*>(res.mutable_data());
    run<false>(s, [&] { s.scene.inside(points_of(a.p.rows), in, a.m, a.w, a.o); });
    return std::move(res);
}

py::object winding_number(const PyScene& s, py::handle points_obj, py::handle out, py::handle threads,
                          py::handle exact, py::handle beta) {
    const arbor::QueryOptions o = options(threads);
    const arbor::WindingOptions w = winding_options(exact, beta);
    const Points p = points(points_obj);
    py::array res = result(out, py::dtype::of<double>(), "float64", alignof(double), p.shape, {points_obj});
    auto* wn = static_cast<double*>(res.mutable_data());
    run<false>(s, [&] { s.scene.winding_number(points_of(p.rows), wn, w, o); });
    return std::move(res);
}

py::object signed_distance(const PyScene& s, py::handle points_obj, py::handle method, py::handle out,
                           py::handle threads, py::handle exact, py::handle beta) {
    const MethodArgs a = method_args(points_obj, method, threads, exact, beta);
    py::array res = result(out, py::dtype::of<float>(), "float32", alignof(float), a.p.shape, {points_obj});
    auto* d = static_cast<float*>(res.mutable_data());
    run<false>(s, [&] { s.scene.signed_distance(points_of(a.p.rows), d, a.m, a.w, a.o); });
    return std::move(res);
}

}  // namespace arbor::python
