/// Scene.update_vertices (spec/python.md, "Added in 0.2"): new positions for a mesh, and the
/// structure refit or rebuilt (docs/refit.md).
#include "update.h"

#include <arbor/arbor.h>

#include <cmath>
#include <cstdint>

#include "args.h"
#include "arrays.h"
#include "py_scene.h"

namespace arbor::python {

void bind_update(py::module_& m) {
    using namespace pybind11::literals;
    auto scene = py::reinterpret_borrow<py::class_<PyScene>>(m.attr("Scene"));
    scene.def(
        "update_vertices",
        [](PyScene& s, py::object geom, py::object vertices, py::object mode, py::object rays) {
            const auto g = std::uint32_t(count_arg(geom, "geom", "a geometry id, an int >= 0", 0xFFFFFFFFll));
            const Rows3 v = rows3(vertices, "vertices");
            arbor::UpdateOptions o;
            o.mode = str_arg(mode, "mode", "\"auto\", \"refit\" or \"rebuild\"");
            if (!rays.is_none()) {
                const float r = number(rays, "rays");
                if (!(r >= 0.0f) || std::isinf(r)) throw py::value_error("rays: expected a finite number >= 0 or None");
                o.rays = double(r);
            }
            run<true>(s, [&] { s.scene.update_vertices(g, v.data, v.count, v.stride, o); });
        },
        "geom"_a, "vertices"_a, py::kw_only(), "mode"_a = "auto", "rays"_a = py::none(),
        "New positions for a mesh, the same faces; the next query sees them, and answers exactly as\n"
        "a scene built from them would.\n\n"
        "A built structure is refit (its boxes recomputed, the tree kept) or rebuilt; with\n"
        "mode=\"auto\", whichever the rays expected before the next update make cheaper: a rebuild\n"
        "when the refitted tree's loss of quality (its SAH cost against the last build's) would cost\n"
        "those rays more time than a rebuild takes. A kd-tree is always rebuilt (its split planes\n"
        "cannot be refit). update_action and update_reason say what was done and why.\n\n"
        "Args:\n"
        "    geom: the mesh's geometry id (as add_mesh returned it; 0 for the first).\n"
        "    vertices: (V, 3) float32 or float64 positions (float64 is converted), V the mesh's vertex\n"
        "        count; every coordinate finite.\n"
        "    mode: \"auto\", \"refit\" (always refit, where the structure can be) or \"rebuild\".\n"
        "    rays: the rays (or points) expected before the next update, for mode=\"auto\"; None: as\n"
        "        many as the scene answered since the last build or update.\n\n"
        "Raises:\n"
        "    TypeError, ValueError: an argument of the wrong type, dtype, shape or value (an unknown\n"
        "        geom, another vertex count, a NaN or infinite coordinate); the one-line message names\n"
        "        it, and the scene is unchanged.\n");
    scene.def_property_readonly(
        "update_action",
        [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.update_action(); }); },
        "str: what the last update_vertices did to the structure: \"refit\", \"rebuild\", or \"none\"\n"
        "(not built yet); \"\" before any update.");
    scene.def_property_readonly(
        "update_reason",
        [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.update_reason(); }); },
        "str: why the last update_vertices refit or rebuilt, with the figures that decided.");
}

}  // namespace arbor::python
