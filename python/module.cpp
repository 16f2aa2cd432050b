/// The Python module `arbor` (../shared/spec/python.md) over the public C++ API: arrays in, arrays
/// out. Arguments are checked and converted with the GIL held (arrays.h, args.h); arbor's work runs
/// with the GIL released (queries.h). Every function's docstring is what help() shows; the type
/// stubs (arbor/_arbor.pyi) say the same in types, and a test keeps the two in agreement.
#include <arbor/arbor.h>

#include <climits>
#include <limits>

#include "args.h"
#include "arrays.h"
#include "instances.h"
#include "py_scene.h"
#include "queries.h"
#include "update.h"

namespace py = pybind11;
using namespace pybind11::literals;
using arbor::python::PyScene;
using arbor::python::run;

namespace {

std::string path_arg(py::handle path, const char* what) {
    try {
        return py::module_::import("os").attr("fspath")(path).cast<std::string>();
    } catch (py::error_already_set&) {
        throw py::type_error(std::string(what) + ": expected a str or os.PathLike path, got " +
                             arbor::python::type_name(path));
    }
}

std::uint32_t add_mesh(PyScene& s, py::object vertices, py::object faces) {
    const arbor::python::Rows3 v = arbor::python::rows3(vertices, "vertices");
    const std::vector<std::uint32_t> f = arbor::python::faces(faces, v.count);
    std::uint32_t id = 0;
    run<true>(s, [&] { id = s.scene.add_mesh(v.data, v.count, v.stride, f.data(), f.size() / 3); });
    return id;
}

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr const char* structures = "brute, bvh-median, bvh-sah, lbvh, kdtree or auto";

// The parts of the queries' docstrings they share.
#define ARBOR_RAYS_DOC                                                                                      \
    "    origins: ray origins, shape (N, 3) or any (..., 3); float32 is read in place, other real dtypes\n" \
    "        are converted. Any array: numpy, the buffer protocol, __array_interface__ or DLPack\n"         \
    "        (e.g. a torch CPU tensor).\n"                                                                  \
    "    directions: ray directions, like origins; the two shapes broadcast (one row for every ray).\n"     \
    "        They need not be unit length: t is measured in units of their length.\n"                       \
    "    tnear, tfar: the range of t searched: numbers, or arrays of the rays' leading shape (...,).\n"
#define ARBOR_THREADS_DOC                                                                          \
    "    threads: threads for this call: 0 = the scene's (build's threads); more than the cores\n" \
    "        = all cores. The answers do not depend on it.\n"
#define ARBOR_WINDING_DOC                                                                          \
    "    exact: winding numbers as the exact sum over every triangle rather than from the tree\n" \
    "        (slower; the same answer on every structure).\n"                                \
    "    beta: the tree's accuracy, a number > 1 (inf: exact): a box's triangles count as one dipole\n" \
    "        beyond beta times their radius; larger is slower and more accurate.\n"
#define ARBOR_RAISES_DOC                                                                               \
    "\nRaises:\n"                                                                                      \
    "    TypeError, ValueError: an argument of the wrong type, dtype or shape; the one-line message\n" \
    "        names it.\n"

}  // namespace

PYBIND11_MODULE(_arbor, m) {
    m.doc() =
        "arbor: ray queries on triangle meshes (closest hit, any hit, all hits, closest point, inside, "
        "winding number, signed distance)";
    m.attr("__version__") = arbor::version();
    m.def("kernel_set", &arbor::kernel_set,
          "The SIMD kernel set arbor's queries run on on this machine: \"avx512\", \"avx2\" or \"sse4\".");

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
        [](py::object path) {
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
        "path"_a,
        "The rays of a .rays file (the record format of `arbor trace`).\n\n"
        "Args:\n"
        "    path: a str or os.PathLike.\n\n"
        "Returns:\n"
        "    (origins, directions, tnear, tfar): float32 arrays of shapes (N, 3), (N, 3), (N,), (N,),\n"
        "    views of one (N, 8) array of the file's records, which the queries read in place.\n\n"
        "Raises:\n"
        "    OSError: the file cannot be read. ValueError: it is not a valid ray file.\n"
        "    TypeError: path is not a path.\n");

    auto scene =
        py::class_<PyScene>(m, "Scene",
                            "Triangle meshes and the acceleration structure built over them.\n\n"
                            "Queries from several Python threads may run at once (each releases the GIL);\n"
                            "add_mesh() and build() wait for the queries running, and queries started\n"
                            "after them wait for them.")
            .def(py::init([](py::object vertices, py::object faces) {
                     auto s = std::make_unique<PyScene>();
                     if (vertices.is_none() != faces.is_none())
                         throw py::type_error(std::string(vertices.is_none() ? "vertices" : "faces") +
                                              ": expected both vertices and faces, or neither");
                     if (!vertices.is_none()) add_mesh(*s, vertices, faces);
                     return s;
                 }),
                 "vertices"_a = py::none(), "faces"_a = py::none(),
                 "A scene of one mesh (geometry 0), or an empty scene when both are None.\n\n"
                 "Args:\n"
                 "    vertices: (V, 3) float32 or float64 positions (float64 is converted).\n"
                 "    faces: (F, 3) vertex numbers of any integer dtype, each in 0..V-1.\n" ARBOR_RAISES_DOC)
            .def_static(
                "load",
                [](py::object path) {
                    const std::string p = path_arg(path, "path");
                    auto s = std::make_unique<PyScene>();
                    py::gil_scoped_release nogil;
                    s->scene = arbor::Scene::load(p);
                    return s;
                },
                "path"_a,
                "A scene of one mesh (geometry 0) from a model file: any file `arbor info` loads (OBJ, PLY,\n"
                "STL, glTF), its triangles numbered as in the file.\n\n"
                "Args:\n"
                "    path: a str or os.PathLike.\n\n"
                "Raises:\n"
                "    OSError: the file cannot be read. ValueError: it cannot be used (the command line's\n"
                "        one-line message). TypeError: path is not a path.\n")
            .def("add_mesh", &add_mesh, "vertices"_a, "faces"_a,
                 "Adds a mesh (its arrays are copied); the next query builds the structure again.\n\n"
                 "Args:\n"
                 "    vertices: (V, 3) float32 or float64 positions (float64 is converted).\n"
                 "    faces: (F, 3) vertex numbers of any integer dtype, each in 0..V-1.\n\n"
                 "Returns:\n"
                 "    int: the mesh's geometry id (0, 1, 2, ... in the order added).\n" ARBOR_RAISES_DOC)
            .def(
                "build",
                [](PyScene& s, py::object accel, py::object threads, py::object max_memory, py::object compact) {
                    const std::string name = arbor::python::str_arg(accel, "accel", structures);
                    const int t = arbor::python::threads_arg(threads, "all cores");
                    const auto budget = std::uint64_t(arbor::python::count_arg(
                        max_memory, "max_memory", "a number of bytes >= 0 (0 = no limit)", LLONG_MAX));
                    if (!py::isinstance<py::bool_>(compact))
                        throw py::type_error("compact: expected True or False, got " +
                                             std::string(py::str(compact.get_type())));
                    const arbor::BuildOptions o{name, t, budget, compact.cast<bool>()};
                    run<true>(s, [&] { s.scene.build(o); });
                },
                "accel"_a = "auto", "threads"_a = 0, "max_memory"_a = 0, "compact"_a = false,
                "Builds the acceleration structure (again, after add_mesh); a query on a scene never built\n"
                "builds it first with the defaults.\n\n"
                "Args:\n"
                "    accel: the structure: \"brute\", \"bvh-median\", \"bvh-sah\", \"lbvh\", \"kdtree\" or \"auto\"\n"
                "        (arbor picks by predicted build + trace time; accel_reason says why).\n"
                "    threads: threads for the build and, by default, for every query: 0 = all cores; more\n"
                "        than the cores = all cores.\n"
                "    max_memory: a budget in bytes for the build (0 = no limit).\n"
                "    compact: the BVHs' compact mode: about half the bytes per triangle, single-ray\n"
                "        and packet traversal (docs/structures.md).\n\n"
                "Raises:\n"
                "    MemoryError: the build would exceed max_memory.\n"
                "    TypeError, ValueError: an argument of the wrong type or value; the message names it.\n")
            .def_property_readonly(
                "triangles",
                [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.triangles(); }); },
                "int: the number of triangles in the scene, over all meshes.")
            .def_property_readonly(
                "load_warnings",
                [](const PyScene& s) {
                    const std::vector<std::string> w =
                        read(s, [](const arbor::Scene& sc) { return sc.load_warnings(); });
                    py::list out;
                    for (const std::string& line : w) out.append(py::str(line));
                    return out;
                },
                "list[str]: what Scene.load read past, one line each naming the file and the data (e.g. a PLY\n"
                "edge element); empty for a scene made from arrays.")
            .def_property_readonly(
                "meshes", [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.meshes(); }); },
                "int: the number of meshes (geometry ids are 0 .. meshes-1).")
            .def_property_readonly(
                "accel", [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.accel(); }); },
                "str: the structure built (\"bvh-sah\", ...), \"\" before the first build.")
            .def_property_readonly(
                "accel_reason",
                [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.accel_reason(); }); },
                "str: with accel=\"auto\", why arbor picked the structure it built.")
            .def_property_readonly(
                "bounds",
                [](const PyScene& s) {
                    py::array_t<float> b({py::ssize_t(2), py::ssize_t(3)});
                    float* lo = b.mutable_data();
                    run<false>(s, [&] { s.scene.bounds(lo, lo + 3); });
                    return b;
                },
                "numpy.ndarray: the scene's box, a (2, 3) float32 array of its lower and upper corners\n"
                "(+inf and -inf for an empty scene).")
            .def("__repr__",
                 [](const PyScene& s) {
                     std::string r;
                     run<false>(s, [&] {
                         r = "<arbor.Scene: " + std::to_string(s.scene.triangles()) + " triangles in " +
                             std::to_string(s.scene.meshes()) + " meshes, " +
                             (s.scene.built() ? "built with " + s.scene.accel() : std::string("not built")) + ">";
                     });
                     return r;
                 })
            .def(
                "intersect",
                [](const PyScene& s, py::object origins, py::object directions, py::object tnear, py::object tfar,
                   py::object out, py::object threads, py::object normals) {
                    return arbor::python::intersect(s, origins, directions, tnear, tfar, out, threads, normals);
                },
                "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "out"_a = py::none(), py::kw_only(),
                "threads"_a = 0, "normals"_a = false,
                "The closest hit of each ray.\n\n"
                "Args:\n" ARBOR_RAYS_DOC
                "    out: None, or an array to write the results into and return: C-contiguous, of the\n"
                "        results' dtype and shape, not overlapping the inputs.\n" ARBOR_THREADS_DOC
                "    normals: also give each hit's unit geometric normal (field normal).\n\n"
                "Returns:\n"
                "    numpy.ndarray: a structured array of the rays' leading shape (...,) (a 0-d array for\n"
                "    one ray of shape (3,)), dtype arbor.hit_dtype: t (float32, in units of the direction's\n"
                "    length), geom and prim (uint32: the mesh and its triangle), u and v (float32: the hit\n"
                "    point is (1-u-v) v0 + u v1 + v v2 of the triangle's corners). A miss: t = inf,\n"
                "    geom = prim = arbor.MISS, u = v = 0. With normals=True the dtype is\n"
                "    arbor.hit_normal_dtype, which adds normal (float32, 3): (v1-v0) x (v2-v0) normalized,\n"
                "    zeros for a miss.\n" ARBOR_RAISES_DOC)
            .def(
                "occluded",
                [](const PyScene& s, py::object origins, py::object directions, py::object tnear, py::object tfar,
                   py::object out, py::object threads) {
                    return arbor::python::occluded(s, origins, directions, tnear, tfar, out, threads);
                },
                "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "out"_a = py::none(), py::kw_only(),
                "threads"_a = 0,
                "Whether each ray hits anything in [tnear, tfar] (any hit: shadow rays).\n\n"
                "Args:\n" ARBOR_RAYS_DOC
                "    out: None, or a C-contiguous bool array of the rays' leading shape to write "
                "into.\n" ARBOR_THREADS_DOC
                "\nReturns:\n"
                "    numpy.ndarray: bool, of the rays' leading shape (...,).\n" ARBOR_RAISES_DOC)
            .def(
                "intersect_all",
                [](const PyScene& s, py::object origins, py::object directions, py::object tnear, py::object tfar,
                   py::object max_hits, py::object out, py::object threads, py::object normals) {
                    return arbor::python::intersect_all(s, origins, directions, tnear, tfar, max_hits, out, threads,
                                                        normals);
                },
                "origins"_a, "directions"_a, "tnear"_a = 0.0, "tfar"_a = inf, "max_hits"_a = 16, py::kw_only(),
                "out"_a = py::none(), "threads"_a = 0, "normals"_a = false,
                "Every triangle each ray crosses in [tnear, tfar], each once, sorted by t.\n\n"
                "Args:\n" ARBOR_RAYS_DOC
                "    max_hits: an int >= 0, the room per ray.\n"
                "    out: None, or a tuple (hits, counts) of C-contiguous arrays of the results' dtypes and\n"
                "        shapes to write into and return.\n" ARBOR_THREADS_DOC
                "    normals: also give each hit's unit geometric normal (field normal), as intersect.\n\n"
                "Returns:\n"
                "    (hits, counts): hits of shape (..., max_hits), dtype arbor.hit_dtype (or\n"
                "    arbor.hit_normal_dtype), the crossings in order of t and misses after the last;\n"
                "    counts (...,) int32, the number of crossings, which may exceed max_hits (then hits\n"
                "    holds the first max_hits).\n" ARBOR_RAISES_DOC)
            .def(
                "closest_point",
                [](const PyScene& s, py::object points, py::object max_distance, py::object out, py::object threads) {
                    return arbor::python::closest_point(s, points, max_distance, out, threads);
                },
                "points"_a, "max_distance"_a = inf, py::kw_only(), "out"_a = py::none(), "threads"_a = 0,
                "The point of the scene closest to each point.\n\n"
                "Args:\n"
                "    points: shape (N, 3), any (..., 3), or one point (3,); float32 is read in place, other\n"
                "        real dtypes are converted; any array, as for intersect.\n"
                "    max_distance: how far to look, in the scene's units (>= 0, inf: no limit): a number,\n"
                "        or an array of the points' leading shape (...,), one per point.\n"
                "    out: None, or a C-contiguous array of arbor.point_dtype and the points' leading shape\n"
                "        to write into and return.\n" ARBOR_THREADS_DOC
                "\nReturns:\n"
                "    numpy.ndarray: a structured array of the points' leading shape (...,) (0-d for one\n"
                "    point), dtype arbor.point_dtype: distance (float32, scene units), geom and prim\n"
                "    (uint32), point (float32, 3), u and v (float32: point = (1-u-v) v0 + u v1 + v v2).\n"
                "    Nothing within max_distance (or a NaN point): distance = inf, geom = prim = "
                "arbor.MISS.\n" ARBOR_RAISES_DOC)
            .def(
                "inside",
                [](const PyScene& s, py::object points, py::object method, py::object out, py::object threads,
                   py::object exact,
                   py::object beta) { return arbor::python::inside(s, points, method, out, threads, exact, beta); },
                "points"_a, "method"_a = "parity", py::kw_only(), "out"_a = py::none(), "threads"_a = 0,
                "exact"_a = false, "beta"_a = 2.0,
                "Whether each point is inside the scene.\n\n"
                "Args:\n"
                "    points: shape (N, 3), any (..., 3), or one point (3,); any array, as for intersect.\n"
                "    method: \"parity\" (the parity of a ray's crossings: for closed meshes; points on the\n"
                "        surface get either answer) or \"winding\" (winding_number >= 0.5: any mesh, also open\n"
                "        or self-overlapping ones; the inside of overlapping parts is their union).\n"
                "    out: None, or a C-contiguous bool array of the points' leading shape to write "
                "into.\n" ARBOR_THREADS_DOC ARBOR_WINDING_DOC
                "\nReturns:\n"
                "    numpy.ndarray: bool, of the points' leading shape (...,) (0-d for one point).\n" ARBOR_RAISES_DOC)
            .def(
                "winding_number",
                [](const PyScene& s, py::object points, py::object out, py::object threads, py::object exact,
                   py::object beta) { return arbor::python::winding_number(s, points, out, threads, exact, beta); },
                "points"_a, py::kw_only(), "out"_a = py::none(), "threads"_a = 0, "exact"_a = false, "beta"_a = 2.0,
                "The generalized winding number of the scene's triangles around each point (Jacobson et al.\n"
                "2013): their signed solid angle over 4 pi. 1 inside a closed mesh whose triangles turn\n"
                "counter-clockwise seen from outside, 0 outside, -1 inside one turned inside out, n inside n\n"
                "overlapping closed parts, fractional near the holes of an open mesh; 1/2 on a face.\n\n"
                "Args:\n"
                "    points: shape (N, 3), any (..., 3), or one point (3,); any array, as for intersect.\n"
                "    out: None, or a C-contiguous float64 array of the points' leading shape to write "
                "into.\n" ARBOR_THREADS_DOC ARBOR_WINDING_DOC
                "\nReturns:\n"
                "    numpy.ndarray: float64, of the points' leading shape (...,) (0-d for one point); NaN for\n"
                "    a point with a NaN or infinite coordinate.\n" ARBOR_RAISES_DOC)
            .def(
                "signed_distance",
                [](const PyScene& s, py::object points, py::object method, py::object out, py::object threads,
                   py::object exact, py::object beta) {
                    return arbor::python::signed_distance(s, points, method, out, threads, exact, beta);
                },
                "points"_a, "method"_a = "parity", py::kw_only(), "out"_a = py::none(), "threads"_a = 0,
                "exact"_a = false, "beta"_a = 2.0,
                "The distance from each point to the closest point of the scene, negative inside.\n\n"
                "Args:\n"
                "    points: shape (N, 3), any (..., 3), or one point (3,); any array, as for intersect.\n"
                "    method: how inside is decided: \"parity\" or \"winding\", as for inside.\n"
                "    out: None, or a C-contiguous float32 array of the points' leading shape to write "
                "into.\n" ARBOR_THREADS_DOC ARBOR_WINDING_DOC
                "\nReturns:\n"
                "    numpy.ndarray: float32, of the points' leading shape (...,) (0-d for one point), in the\n"
                "    scene's units; inf for an empty scene or a point with a NaN or infinite "
                "coordinate.\n" ARBOR_RAISES_DOC)
            .def_property_readonly(
                "closed", [](const PyScene& s) { return read(s, [](const arbor::Scene& sc) { return sc.closed(); }); },
                "bool: every edge is shared by exactly two faces (edges compared by vertex number, so a mesh\n"
                "whose triangles repeat their corners instead of sharing them is open; orientation is not\n"
                "checked). A scene without triangles is closed.");

    arbor::python::bind_update(m);
    arbor::python::def_instances(scene);
}
