#pragma once
/// arbor's public C++ API: the one header a program includes (link arbor::arbor after
/// find_package(arbor)). A Scene of your own triangle arrays or of a model file, one build step,
/// and four batch queries: closest hit, any hit, all hits along a ray, closest point on the surface,
/// plus inside/outside (crossing parity or winding number), winding numbers and signed distances.
///
/// C++14 or later, standard library only: no SIMD, TBB or GLM type appears here, and the installed package
/// sets no compile option on your code. Every error is an arbor::Error with a one-line message.
///
/// Threads: after build(), every const member of a Scene may be called from any number of threads
/// at once; each batch call itself runs on the scene's threads (build's `threads`, default: all
/// cores) or on the threads its QueryOptions ask for. add_mesh(), build() and update_vertices()
/// must not run while another call is using the scene.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(ARBOR_BUILDING_LIBRARY)
#define ARBOR_API __attribute__((visibility("default")))
#else
#define ARBOR_API
#endif

namespace arbor {

/// The library's version, "MAJOR.MINOR.PATCH".
ARBOR_API std::string version();
/// The SIMD kernel set the queries run on ("avx512", "avx2" or "sse4").
ARBOR_API std::string kernel_set();

/// The one exception arbor throws. what() is a single line naming the file, argument or option and
/// the problem; kind() tells input mistakes from unreadable files and exhausted memory.
class ARBOR_API Error : public std::runtime_error {
public:
    enum class Kind {
        invalid_argument,  ///< a bad argument: array size, index out of range, unknown structure name
        bad_file,          ///< a file that was read but cannot be used (malformed, no triangles)
        io,                ///< a file that cannot be opened or read
        out_of_memory,     ///< the memory budget (BuildOptions::max_memory) or the machine's memory
    };
    Error(Kind kind, const std::string& message);
    Kind kind() const noexcept { return kind_; }

private:
    Kind kind_;
};

/// Marks "no triangle": the geom and prim of a miss.
constexpr std::uint32_t invalid_id = 0xFFFFFFFFu;

/// One ray o + t d, t in [tnear, tfar] (the record of a .rays file, 32 bytes). d need not be
/// normalised; t is measured in units of its length. A ray with NaN or infinite components, a zero
/// direction or tfar < tnear misses.
struct Ray {
    float org[3] = {0.0f, 0.0f, 0.0f};
    float tnear = 0.0f;
    float dir[3] = {0.0f, 0.0f, 1.0f};
    float tfar = std::numeric_limits<float>::infinity();
};

/// A ray's answer (24 bytes): the hit at distance t on triangle `prim` (numbered from 0 within its
/// mesh, in face order) of mesh `geom`, at barycentrics (u, v): point = (1-u-v) v0 + u v1 + v v2
/// (in the mesh's own coordinates; for an instance, the instance's transform carries it to the
/// world). `inst` is the instance that placed the mesh (Scene::add_instance), invalid_id for a
/// mesh placed without one. A miss is t = +inf, geom = prim = inst = invalid_id, u = v = 0.
struct Hit {
    float t = std::numeric_limits<float>::infinity();
    std::uint32_t geom = invalid_id;
    std::uint32_t prim = invalid_id;
    float u = 0.0f, v = 0.0f;
    std::uint32_t inst = invalid_id;

    bool hit() const { return prim != invalid_id; }
};

/// A closest-point answer (36 bytes): the nearest point of the scene (in world space), its
/// distance, triangle and barycentrics, and the instance that placed its mesh (invalid_id for a
/// mesh placed without one). Nothing within max_distance (or a non-finite query point):
/// distance = +inf, geom = prim = inst = invalid_id, the rest 0.
struct ClosestPoint {
    float distance = std::numeric_limits<float>::infinity();
    std::uint32_t geom = invalid_id;
    std::uint32_t prim = invalid_id;
    float point[3] = {0.0f, 0.0f, 0.0f};
    float u = 0.0f, v = 0.0f;
    std::uint32_t inst = invalid_id;

    bool found() const { return prim != invalid_id; }
};

/// Rays as a program holds them, read in place: `count` origins and directions (3 floats each,
/// consecutive ones `*_stride` bytes apart; 12 = packed), and tnear / tfar either per ray (a
/// pointer and its stride) or one value for all (null pointer).
struct RayArrays {
    std::size_t count = 0;
    const float* origins = nullptr;
    std::size_t origin_stride = 3 * sizeof(float);
    const float* directions = nullptr;
    std::size_t direction_stride = 3 * sizeof(float);
    const float* tnear = nullptr;
    std::size_t tnear_stride = sizeof(float);
    float tnear_value = 0.0f;
    const float* tfar = nullptr;
    std::size_t tfar_stride = sizeof(float);
    float tfar_value = std::numeric_limits<float>::infinity();

    /// The view of `n` Ray records.
    static RayArrays of(const Ray* rays, std::size_t n) {
        RayArrays r;
        r.count = n;
        if (n == 0) return r;
        r.origins = rays->org, r.directions = rays->dir, r.tnear = &rays->tnear, r.tfar = &rays->tfar;
        r.origin_stride = r.direction_stride = r.tnear_stride = r.tfar_stride = sizeof(Ray);
        return r;
    }
};

/// The rays of a .rays file (the exchange format of `arbor trace`, 32-byte records). Throws
/// Error(io) when the file cannot be read, Error(bad_file) when it is not a valid ray file.
ARBOR_API std::vector<Ray> read_rays(const std::string& path);

/// Points as a program holds them: `count` x, y, z triples, consecutive ones `stride` bytes apart.
struct PointArrays {
    std::size_t count = 0;
    const float* xyz = nullptr;
    std::size_t stride = 3 * sizeof(float);
};

/// One number per point, read in place: values[i] for point i (consecutive ones `stride` bytes
/// apart), or `value` for every point when `values` is null.
struct PointValues {
    const float* values = nullptr;
    std::size_t stride = sizeof(float);
    float value = std::numeric_limits<float>::infinity();
};

/// Options of one batch query; the answers do not depend on them.
struct QueryOptions {
    /// Threads for this call: 0 = the scene's (build's `threads`); counts above the machine's
    /// cores are taken as all cores. Negative counts throw Error(invalid_argument).
    int threads = 0;
};

/// How inside() and signed_distance() decide inside: `parity`, the crossings of a ray (closed
/// meshes; the default), or `winding`, the generalized winding number >= 1/2 (any mesh: open,
/// self-intersecting, with duplicated faces; on closed meshes the two agree off the surface).
enum class InsideMethod { parity, winding };

/// The accuracy of winding_number() (and of InsideMethod::winding).
struct WindingOptions {
    /// true: the exact sum of every triangle's solid angle (time per point grows with the
    /// triangle count; the same answer on every structure). false: the hierarchical evaluation.
    bool exact = false;
    /// Hierarchical evaluation: the triangles of a box of the structure are replaced by one
    /// dipole (their area-weighted normal at their area-weighted centroid) when the point is
    /// farther than beta times their radius from that centroid. Must be > 1; larger is slower and
    /// more accurate (the error of one dipole is at most area * radius / (2 pi (d - radius)^3) at
    /// distance d; +inf: exact). 2 as in libigl.
    double beta = 2.0;
};

struct BuildOptions {
    /// The structure: "bvh-sah", "bvh-median", "lbvh", "kdtree", "brute", or "auto" (arbor picks by
    /// predicted build + trace time, the same decision as the command line's --accel auto).
    std::string accel = "auto";
    /// Threads for the build and for every batch query (0 = all cores; counts above the machine's
    /// cores are taken as all cores, so oneTBB has nothing to warn about).
    int threads = 0;
    /// Upper bound on the build's memory in bytes (0 = no limit); a build that would exceed it
    /// throws Error(out_of_memory) before allocating.
    std::uint64_t max_memory = 0;
    /// Compact mode (the BVHs; ignored by the other structures and by scenes of instances): about
    /// half the structure's bytes per triangle, quantized node boxes and leaves as blocks of
    /// triangles with their own vertex copies, traced as single rays or packets
    /// (docs/structures.md, "Compact mode"). The command line's --compact.
    bool compact = false;
};

/// Options of Scene::update_vertices.
struct UpdateOptions {
    /// "auto" (refit the structure, or rebuild it when the rays expected before the next update
    /// would lose more time on the refitted tree than a rebuild costs), "refit" (always refit where
    /// the structure can be refit) or "rebuild" (always build it again).
    std::string mode = "auto";
    /// Rays (or points) the scene is expected to answer before the next update, for "auto";
    /// negative: as many as it answered since the last build or update. Must be finite.
    double rays = -1.0;
};

class ARBOR_API Scene {
public:
    Scene();
    ~Scene();
    Scene(Scene&&) noexcept;
    Scene& operator=(Scene&&) noexcept;
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    /// A scene of one mesh (geom 0) from a model file (any file `arbor info` loads), its triangles
    /// numbered as a .hits file numbers them.
    static Scene load(const std::string& path);
    /// What load() read past, one line each naming the file and the data (e.g. a PLY `edge`
    /// element, OBJ `l` lines): what `arbor info` prints as warnings. Empty for other scenes.
    std::vector<std::string> load_warnings() const;

    /// Adds a mesh and returns its geometry id (0, 1, 2, ... in the order added). `positions` holds
    /// `vertex_count` x, y, z float triples, consecutive ones `stride` bytes apart (12 = packed;
    /// e.g. sizeof(MyVertex) for positions inside a struct); `indices` holds 3 vertex numbers per
    /// triangle. The arrays are copied. Triangles with a NaN or infinite corner are never hit.
    /// Throws Error(invalid_argument) for an index out of range or a null array.
    std::uint32_t add_mesh(const float* positions, std::size_t vertex_count, std::size_t stride,
                           const std::uint32_t* indices, std::size_t triangle_count);
    /// The same from packed vectors (x, y, z per vertex; 3 indices per triangle).
    std::uint32_t add_mesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices);

    /// Places mesh `geom` once more, by `transform`, and returns the instance id (0, 1, 2, ... in
    /// the order added). `transform` is 12 numbers, a 3x4 matrix in row-major order [A | t]
    /// mapping the mesh's (object) coordinates p to world coordinates A p + t; any invertible A
    /// (rotations, mirrors, non-uniform scales, shears). A mesh with instances is placed only by
    /// them; a mesh without is placed once as it is (inst = invalid_id in its hits). Every query
    /// answers in world space: t along the caller's ray, closest points and distances in world
    /// units, hit_normals of the placed triangle (a mirroring A flips them). The mesh's structure
    /// is built once however often it is placed. Throws Error(invalid_argument) for an unknown
    /// geom, a null transform, a NaN or infinite entry, or a singular A.
    std::uint32_t add_instance(std::uint32_t geom, const double transform[12]);
    std::uint32_t add_instance(std::uint32_t geom, const float transform[12]);
    /// Moves instance `instance` (the next query sees it). Errors as add_instance, or an unknown id.
    void set_transform(std::uint32_t instance, const double transform[12]);
    /// Instances added.
    std::size_t instances() const;

    /// Builds the acceleration structure (again, after add_mesh). Queries on a scene never built
    /// build it first with the default options.
    void build(const BuildOptions& options = {});
    bool built() const;
    /// The structure built ("bvh-sah", ...), empty before build(); and with "auto", why.
    std::string accel() const;
    std::string accel_reason() const;
    std::size_t triangles() const;
    std::size_t meshes() const;

    /// New positions for mesh `geom`, the same triangles: `vertices` holds vertex_count x, y, z
    /// float triples (`stride` bytes apart), as many as add_mesh gave the mesh. The next query
    /// answers for the new positions exactly as a scene built from them would (bit for bit). A
    /// built structure is refit (boxes recomputed, tree kept) or rebuilt, as options.mode says;
    /// "auto" decides by the loss of tree quality and the rays expected (update_reason() says
    /// why). A kd-tree is always rebuilt. Throws Error(invalid_argument) for an unknown geom, a
    /// null array, a stride below 12, a vertex count other than the mesh's, a NaN or infinite
    /// coordinate or an unknown mode; the scene is unchanged then. Must not run while another call
    /// is using the scene.
    void update_vertices(std::uint32_t geom, const float* vertices, std::size_t vertex_count, std::size_t stride,
                         const UpdateOptions& options = {});
    /// The same from a packed vector (x, y, z per vertex).
    void update_vertices(std::uint32_t geom, const std::vector<float>& vertices, const UpdateOptions& options = {});
    /// What the last update_vertices did to the structure: "refit", "rebuild", or "none" (not built
    /// yet: the next query builds it), empty before any update; and why, one line ending with what
    /// the structure's own work took ("[the refit took 12 ms]").
    std::string update_action() const;
    std::string update_reason() const;
    /// Lower and upper corners of the scene's box (+inf / -inf for an empty scene).
    void bounds(float lo[3], float hi[3]) const;

    /// Closest hit of each ray: hits[i] for rays i = 0 .. count-1.
    void intersect(const RayArrays& rays, Hit* hits, const QueryOptions& options = {}) const;
    std::vector<Hit> intersect(const std::vector<Ray>& rays, const QueryOptions& options = {}) const;
    /// Any hit (shadow rays): occluded[i] is true when ray i hits anything in [tnear, tfar].
    void occluded(const RayArrays& rays, bool* occluded, const QueryOptions& options = {}) const;
    std::vector<bool> occluded(const std::vector<Ray>& rays, const QueryOptions& options = {}) const;
    /// All hits: every triangle ray i crosses in [tnear, tfar], each once, sorted by t (then geom,
    /// prim), in hits[i * max_hits ...], the rest of its row filled with misses. counts[i] is the
    /// number of crossings, which may exceed max_hits (then the row holds the first max_hits).
    void intersect_all(const RayArrays& rays, std::size_t max_hits, Hit* hits, std::int32_t* counts,
                       const QueryOptions& options = {}) const;
    /// The unit geometric normal of each hit's triangle, (v1-v0) x (v2-v0) normalized, in the
    /// scene's space: `count` hits read `hit_stride` bytes apart, 3 floats written per hit
    /// `normal_stride` bytes apart (the two may interleave, e.g. a normal stored after each hit).
    /// A miss, or a triangle of zero area, gets (0, 0, 0). Throws Error(invalid_argument) for a
    /// geom or prim that is not in the scene.
    void hit_normals(const Hit* hits, std::size_t count, std::size_t hit_stride, float* normals,
                     std::size_t normal_stride, const QueryOptions& options = {}) const;
    /// Closest point on the scene to each point, within max_distance (>= 0; +inf: no limit): one
    /// distance for all points, or one per point.
    void closest_point(const PointArrays& points, float max_distance, ClosestPoint* out,
                       const QueryOptions& options = {}) const;
    void closest_point(const PointArrays& points, const PointValues& max_distance, ClosestPoint* out,
                       const QueryOptions& options = {}) const;
    std::vector<ClosestPoint> closest_point(const std::vector<float>& xyz,
                                            float max_distance = std::numeric_limits<float>::infinity(),
                                            const QueryOptions& options = {}) const;
    /// Whether each point is inside the scene's closed meshes: the parity of a ray's crossings, a
    /// second direction where the first meets an edge or vertex exactly. Meaningful for closed
    /// meshes; points on the surface get either answer.
    void inside(const PointArrays& points, bool* inside, const QueryOptions& options = {}) const;
    std::vector<bool> inside(const std::vector<float>& xyz, const QueryOptions& options = {}) const;
    /// The same by `method`: parity as above, or winding_number(points, winding) >= 0.5 (meaningful
    /// for open meshes too; the inside of overlapping closed parts is their union).
    void inside(const PointArrays& points, bool* inside, InsideMethod method, const WindingOptions& winding = {},
                const QueryOptions& options = {}) const;
    std::vector<bool> inside(const std::vector<float>& xyz, InsideMethod method, const WindingOptions& winding = {},
                             const QueryOptions& options = {}) const;

    /// The generalized winding number of the scene's triangles around each point (Jacobson et al.
    /// 2013): the signed solid angle they subtend over 4 pi, summed in double. 1 inside a closed
    /// mesh whose triangles turn counter-clockwise seen from outside, 0 outside, -1 inside one
    /// turned inside out, n inside n nested or overlapping closed parts, fractional near the holes
    /// of an open mesh. A point exactly in a triangle's plane gets nothing from that triangle, so a
    /// point exactly on a closed mesh gets 1/2 on a face and the interior's share of the directions
    /// on an edge or a corner (1/4 on a cube's edge); a point a rounding error off a face gets 0 or
    /// 1 by the side it lies on. A non-finite point: NaN. Triangles with a NaN or infinite corner
    /// are left out. The hierarchical evaluation runs on the structure built (the BVHs' own trees;
    /// the kd-tree builds an internal BVH; brute sums every triangle) and makes its data on the
    /// first call after a build; results do not depend on the thread count. Throws
    /// Error(invalid_argument) for beta <= 1 or NaN.
    void winding_number(const PointArrays& points, double* out, const WindingOptions& winding = {},
                        const QueryOptions& options = {}) const;
    std::vector<double> winding_number(const std::vector<float>& xyz, const WindingOptions& winding = {},
                                       const QueryOptions& options = {}) const;

    /// The distance to the closest point of the scene, negative inside (by `method`, as inside()).
    /// An empty scene or a non-finite point: +inf.
    void signed_distance(const PointArrays& points, float* out, InsideMethod method = InsideMethod::parity,
                         const WindingOptions& winding = {}, const QueryOptions& options = {}) const;
    std::vector<float> signed_distance(const std::vector<float>& xyz, InsideMethod method = InsideMethod::parity,
                                       const WindingOptions& winding = {}, const QueryOptions& options = {}) const;

    /// True when every edge is shared by exactly two triangles (of the same mesh: meshes share no
    /// vertices). Edges are compared by vertex number, not position (vertices are not welded: a
    /// file whose triangles repeat their corners instead of sharing them is open); orientation is
    /// not checked. A scene without triangles is closed. Computed on the first call after add_mesh.
    bool closed() const;

    struct Impl;  ///< opaque: the library's own

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace arbor
