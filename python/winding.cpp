/// The winding-number queries of the Python module (winding.h): argument checks with the GIL held,
/// the work through the module's runner (GIL released, shared lock).
#include "arrays.h"
#include "winding.h"

#include <pybind11/numpy.h>

#include <string>

namespace arbor::python {

namespace {

using namespace pybind11::literals;

arbor::InsideMethod inside_method(const std::string& method) {
    if (method == "parity") return arbor::InsideMethod::parity;
    if (method == "winding") return arbor::InsideMethod::winding;
    throw py::value_error("method: expected \"parity\" or \"winding\", got \"" + method + "\"");
}

arbor::WindingOptions winding_options(bool exact, py::handle beta) {
    arbor::WindingOptions o;
    o.exact = exact;
    if (!py::isinstance<py::float_>(beta) && !py::isinstance<py::int_>(beta))
        throw py::type_error("beta: expected a number > 1 (inf: exact)");
    o.beta = beta.cast<double>();
    if (!(o.beta > 1.0))
        throw py::value_error("beta: expected a number > 1 (inf: exact), got " + std::to_string(o.beta));
    return o;
}

arbor::PointArrays points_of(const Rows3& p) { return {p.count, p.data, p.stride}; }

}  // namespace

void add_winding(py::object cls, SceneRunner run) {
    const auto method = [&](const char* name, py::cpp_function f) { py::setattr(cls, name, f); };
    method(
        "winding_number",
        py::cpp_function(
            [run](py::handle self, py::handle points, bool exact, py::handle beta) {
                const Rows3 p = rows3(points, "points");
                const arbor::WindingOptions o = winding_options(exact, beta);
                py::array_t<double> out(py::ssize_t(p.count));
                double* w = out.mutable_data();
                run(self, [&](const arbor::Scene& s) { s.winding_number(points_of(p), w, o); });
                return out;
            },
            py::name("winding_number"), py::is_method(cls), "points"_a, py::kw_only(), "exact"_a = false,
            "beta"_a = 2.0,
            "Generalized winding number of the scene's triangles around each point: an (N,) float64 array (1 inside a "
            "closed outward mesh, 0 outside, fractional near holes; NaN for a non-finite point). beta: a box's "
            "triangles become one dipole beyond beta times their radius (> 1; larger is slower and more accurate); "
            "exact=True sums every triangle."));

    // After the module's inside(points): pybind11 tries overloads in order, so inside(points) stays
    // the module's and a call with `method` (or the winding options) comes here.
    method("inside",
           py::cpp_function(
               [run](py::handle self, py::handle points, const std::string& method, bool exact, py::handle beta) {
                   const arbor::InsideMethod m = inside_method(method);
                   const Rows3 p = rows3(points, "points");
                   const arbor::WindingOptions o = winding_options(exact, beta);
                   py::array_t<bool> out(py::ssize_t(p.count));
                   bool* in = out.mutable_data();
                   run(self, [&](const arbor::Scene& s) { s.inside(points_of(p), in, m, o); });
                   return out;
               },
               py::name("inside"), py::is_method(cls), py::sibling(py::getattr(cls, "inside", py::none())), "points"_a,
               "method"_a = "parity", py::kw_only(), "exact"_a = false, "beta"_a = 2.0,
               "Whether each point is inside: an (N,) bool array. method=\"parity\" (default): crossing parity, for "
               "closed "
               "meshes; \"winding\": winding number >= 0.5 (any mesh; exact and beta as in winding_number)."));

    method("signed_distance",
           py::cpp_function(
               [run](py::handle self, py::handle points, const std::string& method, bool exact, py::handle beta) {
                   const arbor::InsideMethod m = inside_method(method);
                   const Rows3 p = rows3(points, "points");
                   const arbor::WindingOptions o = winding_options(exact, beta);
                   py::array_t<float> out(py::ssize_t(p.count));
                   float* d = out.mutable_data();
                   run(self, [&](const arbor::Scene& s) { s.signed_distance(points_of(p), d, m, o); });
                   return out;
               },
               py::name("signed_distance"), py::is_method(cls), "points"_a, "method"_a = "parity", py::kw_only(),
               "exact"_a = false, "beta"_a = 2.0,
               "Distance to the closest point of the scene, negative inside (by method, as inside()): an (N,) float32 "
               "array; +inf for an empty scene or a non-finite point."));

    const py::cpp_function closed(
        [run](py::handle self) {
            bool c = false;
            run(self, [&](const arbor::Scene& s) { c = s.closed(); });
            return c;
        },
        py::is_method(cls));
    py::setattr(cls, "closed",
                py::module_::import("builtins")
                    .attr("property")(closed, py::none(), py::none(),
                                      "True when every edge is shared by exactly two triangles (by vertex number: "
                                      "vertices are not welded; orientation is not checked)."));
}

}  // namespace arbor::python
