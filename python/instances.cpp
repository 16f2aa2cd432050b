#include "instances.h"

#include <pybind11/numpy.h>

#include <array>
#include <cstdint>
#include <string>

#include "args.h"
#include "arrays.h"

namespace arbor::python {

namespace py = pybind11;
using namespace pybind11::literals;

namespace {

/// `obj` as a 3x4 transform: any array (or nested sequence) of shape (3, 4) of a real dtype;
/// TypeError (not an array of numbers) or ValueError (another shape) naming `what`.
std::array<double, 12> transform_arg(py::handle obj, const char* what) {
    const std::string w(what);
    py::array a;
    try {
        a = py::module_::import("numpy").attr("asarray")(obj);
    } catch (py::error_already_set&) {
        throw py::type_error(w + ": expected a (3, 4) array of floats (object -> world), got " + type_name(obj));
    }
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(w + ": expected a (3, 4) array of floats (object -> world), got " + type_name(obj) +
                             " of dtype " + py::str(a.dtype()).cast<std::string>());
    Shape shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape.push_back(a.shape(i));
    if (shape != Shape{3, 4})
        throw py::value_error(w + ": expected shape (3, 4) (rows [A | t] of p -> A p + t), got " + shape_str(shape));
    const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    std::array<double, 12> t{};
    for (std::size_t i = 0; i < 12; ++i) t[i] = d.data()[i];
    return t;
}

constexpr const char* transform_doc =
    "    transform: a (3, 4) array of floats (float32 or float64; any array or nested list), row-major\n"
    "        [A | t]: the mesh's point p is placed at A p + t in the world. Any invertible A: rotations,\n"
    "        mirrors (det A < 0: its triangles face the other way), non-uniform scales, shears.\n";

}  // namespace

void def_instances(py::class_<PyScene>& cls) {
    cls.def(
           "add_instance",
           [](PyScene& s, py::object geom, py::object transform) {
               const auto g = std::uint32_t(count_arg(geom, "geom", "an int >= 0 (a geometry id)", 0xFFFFFFFFll));
               const std::array<double, 12> t = transform_arg(transform, "transform");
               std::uint32_t id = 0;
               run<true>(s, [&] { id = s.scene.add_instance(g, t.data()); });
               return id;
           },
           "geom"_a, "transform"_a,
           (std::string("Places mesh `geom` once more, by an affine transform; returns the instance id (0, 1, ...).\n"
                        "A mesh with instances is placed only by them; a mesh without is placed once as it is.\n"
                        "Once the scene holds instances, hit and closest-point records have the field inst\n"
                        "(uint32; arbor.MISS for a miss and for meshes placed without an instance); every query\n"
                        "answers in world space. The next query builds the structure again (each mesh's\n"
                        "structure once, however often it is placed).\n\n"
                        "Args:\n"
                        "    geom: a geometry id (from add_mesh; 0 for the first mesh).\n") +
            transform_doc +
            "\nReturns:\n"
            "    int: the instance id.\n\n"
            "Raises:\n"
            "    TypeError: geom is not an int, or transform not an array of numbers.\n"
            "    ValueError: an unknown geom, a transform of another shape, with NaN or infinite entries,\n"
            "        or a singular A; the one-line message names the argument.\n")
               .c_str())
        .def(
            "set_transform",
            [](PyScene& s, py::object inst, py::object transform) {
                const auto i = std::uint32_t(count_arg(inst, "inst", "an int >= 0 (an instance id)", 0xFFFFFFFFll));
                const std::array<double, 12> t = transform_arg(transform, "transform");
                run<true>(s, [&] { s.scene.set_transform(i, t.data()); });
            },
            "inst"_a, "transform"_a,
            (std::string("Moves instance `inst` to a new transform; the next query sees it.\n\n"
                         "Args:\n"
                         "    inst: an instance id (from add_instance).\n") +
             transform_doc +
             "\nRaises:\n"
             "    TypeError, ValueError: as add_instance (an unknown inst is a ValueError).\n")
                .c_str())
        .def_property_readonly(
            "instances",
            [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.instances(); }); },
            "int: the number of instances (instance ids are 0 .. instances-1).");
}

}  // namespace arbor::python
