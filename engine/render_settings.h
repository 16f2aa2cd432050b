#pragma once
/// What a render is asked to do (RenderSettings) and what it did (RenderStats: rays per kind).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace arbor::engine {

/// primary: first hits only (colour = albedo x |cos|, plus depth/normal/albedo layers);
/// ao: ambient occlusion; direct: point and area lights with shadow rays, mirror bounces to a
/// depth (Whitted style); path: diffuse global illumination with next-event estimation; cost: what
/// each camera ray costs the structure (nodes visited, triangles tested: layers nodes and tris).
enum class IntegratorKind { primary, ao, direct, path, cost };

std::string_view to_string(IntegratorKind k);
std::optional<IntegratorKind> parse_integrator(std::string_view s);
/// "primary, ao, direct, path, cost", for messages.
std::string integrator_names();

/// Extra image layers beside R, G, B (from the first hit of each sample).
struct Layers {
    bool depth = false;   ///< Z: camera-space depth, the smallest over the pixel's samples (+inf: no hit)
    bool normal = false;  ///< N.X N.Y N.Z: mean unit geometric normal facing the camera (0 on misses)
    bool albedo = false;  ///< A.R A.G A.B: mean diffuse reflectance (0 on misses)
    bool any() const { return depth || normal || albedo; }
};

struct RenderSettings {
    int width = 640, height = 480;
    int spp = 4;  ///< samples per pixel, stratified sub-pixel jitter
    IntegratorKind integrator = IntegratorKind::direct;
    int max_depth = -1;       ///< bounces after the camera ray; -1: 3 for direct, 8 for path
    int tile = 16;            ///< tile edge in pixels
    std::optional<Layers> layers;  ///< unset: all three for primary, none otherwise
    int ao_samples = 4;       ///< AO rays per camera sample
    float ao_radius = -1.0f;  ///< AO ray length; < 0: 0.25 x the scene's bounding-box diagonal
    int rr_depth = 3;         ///< Russian roulette from this bounce on (path)
    std::uint32_t seed = 0;   ///< selects an independent set of random streams
    bool jitter = true;       ///< false: every sample goes through the pixel centre (tests)
    bool progress = false;    ///< a progress bar on stderr when it is a terminal

    int depth() const {
        return max_depth >= 0 ? max_depth : integrator == IntegratorKind::path ? 8 : 3;
    }
    Layers resolved_layers() const {
        if (layers) return *layers;
        const bool primary = integrator == IntegratorKind::primary;
        return {primary, primary, primary};  // none for cost: its layers are nodes and tris
    }
};

/// The kinds of rays a renderer traces, counted separately.
enum class RenderRayKind { primary, shadow, mirror, diffuse, ao, count };
constexpr std::size_t render_ray_kind_count = std::size_t(RenderRayKind::count);
std::string_view to_string(RenderRayKind k);

struct RenderStats {
    double seconds = 0.0;  ///< wall time of the render (not the structure's build)
    std::array<std::uint64_t, render_ray_kind_count> rays{};
    std::array<double, render_ray_kind_count> trace_seconds{};  ///< time inside the structure, summed over threads
    int threads = 1;

    std::uint64_t count(RenderRayKind k) const { return rays[std::size_t(k)]; }
    std::uint64_t total() const;
    /// One line: "12.3 Mrays/s overall; primary 1.0M at 40.2 Mrays/s, shadow ..." (kinds traced only).
    /// Per kind, the rate is rays / (time inside the structure / threads).
    std::string summary() const;
};

}  // namespace arbor::engine
