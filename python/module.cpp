/// The Python module `arbor` (../shared/spec/python.md) over the public C++ API: arrays in, arrays
/// out. Arguments are checked and converted with the GIL held (arrays.h); arbor's work runs with the
/// GIL released, on every thread of the scene's arena. A scene is guarded by a reader-writer lock:
/// queries from several Python threads share it, add_mesh() and build() wait for them.
#include "arrays.h"
#include "winding.h"

#include <arbor/arbor.h>

#include <pybind11/stl.h>

#include <cstring>
#include <limits>
#include <mutex>
#include <shared_mutex>

namespace py = pybind11;
using namespace pybind11::literals;

namespace {

using arbor::python::Rows3;

struct PyScene {
    arbor::Scene scene;
    mutable std::shared_mutex mutex;
};

std::string path_arg(py::handle path, const char* what) {
    try {
        return py::module_::import("os").attr("fspath")(path).cast<std::string>();
    } catch (py::error_already_set&) {
        throw py::type_error(std::string(what) + ": expected a str or os.PathLike path, got " +
                             py::str(py::type::handle_of(path).attr("__name__")).cast<std::string>());
    }
}

/// Runs `f` on the scene with the GIL released: shared (queries) or exclusive (changes).
template <bool Exclusive, class F> void run(const PyScene& s, F&& f) {
    py::gil_scoped_release nogil;
    if constexpr (Exclusive) {
        const std::unique_lock lock(s.mutex);
        f();
    } else {
        const std::shared_lock lock(s.mutex);
        f();
    }
}

std::uint32_t add_mesh(PyScene& s, py::handle vertices, py::handle faces) {
    const Rows3 v = arbor::python::rows3(vertices, "vertices");
    const std::vector<std::uint32_t> f = arbor::python::faces(faces, v.count);
    std::uint32_t id = 0;
    run<true>(s, [&] { id = s.scene.add_mesh(v.data, v.count, v.stride, f.data(), f.size() / 3); });
    return id;
}

/// The rays of a query: origins and directions of N rows (one row of either is broadcast to the
/// other's N), tnear and tfar numbers or (N,) arrays.
struct Rays {
    Rows3 org, dir;
    arbor::python::PerRay tnear, tfar;
    arbor::RayArrays view;
};

Rays rays(py::handle origins, py::handle directions, py::handle tnear, py::handle tfar) {
    Rays r;
    r.org = arbor::python::rows3(origins, "origins");
    r.dir = arbor::python::rows3(directions, "directions");
    if (r.org.count == 1 && r.dir.count != 1) r.org.stride = 0, r.org.count = r.dir.count;
    if (r.dir.count == 1 && r.org.count != 1) r.dir.stride = 0, r.dir.count = r.org.count;
    if (r.org.count != r.dir.count)
        throw py::value_error("directions: expected " + std::to_string(r.org.count) + " rows like origins (or 1), got " +
                              std::to_string(r.dir.count));
    const std::size_t n = r.org.count;
    r.tnear = arbor::python::per_ray(tnear, "tnear", n);
    r.tfar = arbor::python::per_ray(tfar, "tfar", n);
    arbor::RayArrays& v = r.view;
    v.count = n;
    v.origins = r.org.data, v.origin_stride = r.org.stride;
    v.directions = r.dir.data, v.direction_stride = r.dir.stride;
    v.tnear = r.tnear.data, v.tnear_stride = r.tnear.stride, v.tnear_value = r.tnear.value;
    v.tfar = r.tfar.data, v.tfar_stride = r.tfar.stride, v.tfar_value = r.tfar.value;
    return r;
}

/// The array a query's results go to: a new (N,) array of `dtype`, or the caller's `out` once
/// checked (arrays.h: check_out_array). The query's own inputs are what `out` must not overlap.
py::array result(py::handle out, const py::dtype& dtype, const char* dtype_name, std::size_t alignment, const Rays& r,
                 std::initializer_list<py::handle> inputs) {
    if (out.is_none()) return py::array(dtype, std::vector<py::ssize_t>{py::ssize_t(r.view.count)});
    arbor::python::check_out_array(out, dtype, dtype_name, alignment, r.view.count, inputs);
    return py::reinterpret_borrow<py::array>(out);
}

arbor::PointArrays points_of(const Rows3& p) { return {p.count, p.data, p.stride}; }

constexpr float inf = std::numeric_limits<float>::infinity();

}  // namespace

PYBIND11_MODULE(_arbor, m) {
    m.doc() = "arbor: ray queries on triangle meshes (closest hit, any hit, all hits, closest point, inside)";
    m.attr("__version__") = arbor::version();
    m.def("kernel_set", &arbor::kernel_set, "The SIMD kernel set arbor's queries run on: avx512, avx2 or sse4.");

    // arbor::Error by kind: unreadable files are OSError, exhausted memory MemoryError, the rest
    // (bad files, bad arguments) ValueError, each with the C++ API's one-line message.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const arbor::Error& e) {
            PyObject* type = PyExc_ValueError;
            if (e.kind() == arbor::Error::Kind::io) type = PyExc_OSError;
            if (e.kind() == arbor::Error::Kind::out_of_memory) type = PyExc_MemoryError;
            PyErr_SetString(type, e.what());
        }
    });

    m.def(
        "read_rays",
        [](py::handle path) {
            const std::string p = path_arg(path, "path");
            // The records stay where the file was read into: the (N, 8) float32 array below owns
            // them (no copy), and the four arrays are views of its columns, which the queries read
            // in place (origin, tnear, direction, tfar: rayfile.md's record).
            static_assert(sizeof(arbor::Ray) == 8 * sizeof(float));
            auto rays = std::make_unique<std::vector<arbor::Ray>>();
            {
                py::gil_scoped_release nogil;
                *rays = arbor::read_rays(p);
            }
            const auto n = py::ssize_t(rays->size());
            float* data = reinterpret_cast<float*>(rays->data());
            const py::capsule owner(rays.get(), [](void* v) { delete static_cast<std::vector<arbor::Ray>*>(v); });
            rays.release();
            const py::array_t<float> all({n, py::ssize_t(8)}, data, owner);
            const py::object cols = all.attr("__getitem__");
            const py::slice every{py::none(), py::none(), py::none()};
            return py::make_tuple(cols(py::make_tuple(every, py::slice(0, 3, 1))), cols(py::make_tuple(every, py::slice(4, 7, 1))),
                                  cols(py::make_tuple(every, 3)), cols(py::make_tuple(every, 7)));
        },
        "path"_a, "origins, directions, tnear, tfar of a .rays file: (N, 3), (N, 3), (N,), (N,) float32 arrays (views of "
        "one (N, 8) array of the file's records, which the queries read in place).");

    py::class_<PyScene>(m, "Scene", "Triangle meshes and the acceleration structure built over them.")
        .def(py::init([](py::handle vertices, py::handle faces) {
                 auto s = std::make_unique<PyScene>();
                 if (vertices.is_none() != faces.is_none())
                     throw py::type_error(std::string(vertices.is_none() ? "vertices" : "faces") +
                                          ": expected both vertices and faces, or neither");
                 if (!vertices.is_none()) add_mesh(*s, vertices, faces);
                 return s;
             }),
             "vertices"_a = py::none(), "faces"_a = py::none(),
             "A scene of one mesh: vertices (V, 3) float, faces (F, 3) int (or an empty scene).")
        .def_static(
            "load",
            [](py::handle path) {
                const std::string p = path_arg(path, "path");
                auto s = std::make_unique<PyScene>();
                py::gil_scoped_release nogil;
                s->scene = arbor::Scene::load(p);
                return s;
            },
            "path"_a, "A scene of one mesh (geometry 0) from a model file.")
        .def("add_mesh", &add_mesh, "vertices"_a, "faces"_a, "Adds a mesh; returns its geometry id.")
        .def(
            "build",
            [](PyScene& s, const std::string& accel, int threads, py::handle max_memory) {
                if (!py::isinstance<py::int_>(max_memory) || max_memory.cast<py::int_>() < py::int_(0))
                    throw py::value_error("max_memory: expected a number of bytes >= 0 (0 = no limit)");
                arbor::BuildOptions o{accel, threads, max_memory.cast<std::uint64_t>()};
                run<true>(s, [&] { s.scene.build(o); });
            },
            "accel"_a = "auto", "threads"_a = 0, "max_memory"_a = 0,
            "Builds the structure: brute, bvh-median, bvh-sah, lbvh, kdtree or auto; threads 0 = all cores.")
        .def_property_readonly("triangles", [](const PyScene& s) { return s.scene.triangles(); })
        .def_property_readonly("meshes", [](const PyScene& s) { return s.scene.meshes(); })
        .def_property_readonly("accel", [](const PyScene& s) { return s.scene.accel(); })
        .def_property_readonly("accel_reason", [](const PyScene& s) { return s.scene.accel_reason(); })
        .def_property_readonly("bounds",
                               [](const PyScene& s) {
                                   py::array_t<float> b({py::ssize_t(2), py::ssize_t(3)});
                                   s.scene.bounds(b.mutable_data(), b.mutable_data() + 3);
                                   return b;
                               })
        .def("__repr__",
             [](const PyScene& s) {
                 return "<arbor.Scene: " + std::to_string(s.scene.triangles()) + " triangles in " +
                        std::to_string(s.scene.meshes()) + " meshes, " +
                        (s.scene.built() ? "built with " + s.scene.accel() : std::string("not built")) + ">";
             })
        .def(
            "intersect",
            [](const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar, py::handle out) {
                const Rays r = rays(origins, directions, tnear, tfar);
                py::array res = result(out, arbor::python::hit_dtype(), "arbor.hit_dtype", alignof(arbor::Hit), r, {origins, directions, tnear, tfar});
                auto* hits = static_cast<arbor::Hit*>(res.mutable_data());
                run<false>(s, [&] { s.scene.intersect(r.view, hits); });
                return res;
            },
            "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "out"_a = py::none(),
            "Closest hit per ray: a structured (N,) array of t, geom, prim, u, v (a miss: t = inf, ids 0xFFFFFFFF); "
            "with out= (a contiguous (N,) array of arbor.hit_dtype), written there and returned.")
        .def(
            "occluded",
            [](const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar, py::handle out) {
                const Rays r = rays(origins, directions, tnear, tfar);
                py::array res = result(out, py::dtype::of<bool>(), "bool", alignof(bool), r, {origins, directions, tnear, tfar});
                bool* occ = static_cast<bool*>(res.mutable_data());
                run<false>(s, [&] { s.scene.occluded(r.view, occ); });
                return res;
            },
            "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "out"_a = py::none(),
            "Any hit per ray: an (N,) bool array; with out= (a contiguous (N,) bool array), written there and returned.")
        .def(
            "intersect_all",
            [](const PyScene& s, py::handle origins, py::handle directions, py::handle tnear, py::handle tfar,
               py::ssize_t max_hits) {
                if (max_hits < 0) throw py::value_error("max_hits: expected a number >= 0, got " + std::to_string(max_hits));
                const Rays r = rays(origins, directions, tnear, tfar);
                const auto n = py::ssize_t(r.view.count);
                py::array hits(arbor::python::hit_dtype(), std::vector<py::ssize_t>{n, max_hits});
                py::array_t<std::int32_t> counts(n);
                auto* h = static_cast<arbor::Hit*>(hits.mutable_data());
                std::int32_t* c = counts.mutable_data();
                run<false>(s, [&] { s.scene.intersect_all(r.view, std::size_t(max_hits), h, c); });
                return py::make_tuple(hits, counts);
            },
            "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "max_hits"_a = 16,
            "Every crossing per ray, sorted by t: hits (N, max_hits) and counts (N,) int32 (may exceed max_hits).")
        .def(
            "closest_point",
            [](const PyScene& s, py::handle points, py::handle max_distance) {
                const Rows3 p = arbor::python::rows3(points, "points");
                const float reach = arbor::python::number(max_distance, "max_distance");
                if (!(reach >= 0.0f)) throw py::value_error("max_distance: expected a number >= 0 (inf: no limit)");
                py::array out(arbor::python::point_dtype(), std::vector<py::ssize_t>{py::ssize_t(p.count)});
                auto* res = static_cast<arbor::ClosestPoint*>(out.mutable_data());
                run<false>(s, [&] { s.scene.closest_point(points_of(p), reach, res); });
                return out;
            },
            "points"_a, "max_distance"_a = inf,
            "Closest point on the scene per point: a structured (N,) array of distance, geom, prim, point, u, v.")
        .def(
            "inside",
            [](const PyScene& s, py::handle points) {
                const Rows3 p = arbor::python::rows3(points, "points");
                py::array_t<bool> out(py::ssize_t(p.count));
                bool* in = out.mutable_data();
                run<false>(s, [&] { s.scene.inside(points_of(p), in); });
                return out;
            },
            "points"_a, "Whether each point is inside the scene's closed meshes: an (N,) bool array.");
    arbor::python::add_winding(m.attr("Scene"), [](py::handle self, const arbor::python::SceneWork& work) {
        const PyScene& s = self.cast<const PyScene&>();
        run<false>(s, [&] { work(s.scene); });
    });
}
