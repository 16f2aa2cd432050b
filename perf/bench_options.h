#pragma once
/// What the benchmark runs: the matrix (scenes x ray kinds x structures x paths x threads, plus
/// the Embree modes) and how hard it measures. Defaults are the full report; `quick()` the
/// two-minute one.
#include <cstdint>
#include <string>
#include <vector>

namespace arbor::perf {

struct BenchOptions {
    /// Scene names to run ("all", or any of: models, stadium, interior, grass, soup, scaling,
    /// tiny, or a model stem / replicated-1eK; a leading '?' skips a missing model); see plan_scenes().
    std::vector<std::string> scenes{"models", "stadium", "interior", "grass", "soup", "scaling"};
    /// Folder of *.obj models (../shared/scenes/models); missing = no model scenes.
    std::string models_dir;
    /// Largest replicated scene, as a power of ten (3..7).
    int scaling_max_exp = 7;
    /// Sizes of the procedural scenes.
    std::size_t grass_blades = 200000, soup_triangles = 200000;
    int interior_detail = 4;
    /// Ray kinds: primary, shadow, diffuse, random.
    std::vector<std::string> kinds{"primary", "shadow", "diffuse", "random"};
    /// Structures to try (those make_accel cannot build are reported and skipped).
    std::vector<std::string> structures{"bvh-median", "bvh-sah", "lbvh", "kdtree"};
    /// Also time brute (only sensible on tiny scenes).
    bool time_brute = false;
    /// Rays per (scene, kind).
    std::size_t rays = std::size_t(1) << 14;
    /// Rays per (scene, kind) on the replicated scaling scenes (only primary and diffuse run there).
    std::size_t scaling_rays = std::size_t(1) << 14;
    /// Wall-time budget for timing one (scene, kind): when the repeats would take longer, fewer
    /// rays of the same kind are timed (a coarser image, same seed), at least min_timed_rays.
    double kind_seconds = 2.0;
    /// One timing repeats the pass over the timed rays until this many ms have passed (per-pass
    /// time = elapsed / passes), so that no timing is a single scheduler slice.
    double min_timed_ms = 6.0;
    std::size_t min_timed_rays = std::size_t(1) << 13;
    /// Scenes above this many triangles are built once, timed at all threads only, and run Embree's
    /// default mode only.
    std::size_t big_scene = 2000000;
    /// Scenes above this many triangles are built once per thread count (no repeats).
    std::size_t single_build_above = 500000;
    /// A structure whose build on a scene is predicted (from its largest earlier build at all
    /// threads, scaled by N log N) to take longer than this many seconds is skipped there (noted).
    double max_build_seconds = 60.0;
    /// Timed repeats per configuration (median, min, max); builds repeat `build_repeats` times
    /// (once on scenes above 2M triangles).
    int repeats = 5;
    int build_repeats = 2;
    /// Thread counts; 0 means all hardware threads.
    std::vector<int> threads{1, 0};
    /// Brute-force validation budget: about this many ray/triangle tests per (scene, kind); the
    /// sample is budget / triangles rays, clamped to [min_sample, max_sample].
    double brute_budget = 5e8;
    std::size_t min_sample = 32, max_sample = 512;
    /// Rays per (scene, kind, structure) traced in the statistics mode (TraceCounters).
    std::size_t count_sample = 2048;
    /// Ray budgets for the build + trace totals.
    std::vector<double> budgets{1e6, 16e6, 256e6};
    /// Run the Embree peer when it is built.
    bool embree = true;
    /// Embree modes beyond the default (MEDIUM, not robust, every call): HIGH and ROBUST with
    /// rtcIntersect1 and the stream call (Embree 3 only).
    bool embree_variants = true;
    /// Evaluate --accel auto on every (scene, kind, threads, budget).
    bool evaluate_auto = true;
    std::uint64_t seed = 1;
    /// Print progress lines on stderr.
    bool verbose = true;
    /// Under `mpirun arbor bench`: this process's rank (recorded in every row; -1 without MPI) and
    /// a tag for its progress lines (" r1" -> "[bench r1 12.3s]").
    int rank = -1;
    std::string log_tag;

    /// The two-minute variant: tiny and small scenes, fewer rays and repeats.
    static BenchOptions quick();
};

}  // namespace arbor::perf
