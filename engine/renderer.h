#pragma once
/// The tile renderer. tbb::parallel_for over a blocked_range2d of 16x16 tiles; each tile runs the
/// integrator, which hands the structure whole batches per tile (camera rays, then shadow rays,
/// then bounce rays), so the structure can trace coherent batches as packets. Random numbers
/// depend only on (seed, pixel, sample, dimension) and every tile is summed in a fixed order, so
/// the image is bit-identical for any number of threads.
#include "accel/interface/accel.h"
#include "engine/image.h"
#include "engine/lights.h"
#include "engine/plan.h"
#include "engine/render_settings.h"
#include "engine/scene.h"
#include "engine/tile_source.h"

namespace arbor::engine {

/// Renders `scene` with `accel` (built over scene.mesh) following `plan` (from make_plan with the
/// same settings). The image has channels R, G, B, then Z, N.X N.Y N.Z, A.R A.G A.B as the plan's
/// layers say (cost integrator: nodes, tris). `stats` (optional) receives the rays traced per kind and the times.
/// `tiles` (optional) decides which tiles this process renders (engine/tile_source.h); without it, all.
Image render(const Scene& scene, const LightSet& lights, const RenderPlan& plan, const accel::Accel& accel,
             const RenderSettings& settings, RenderStats* stats = nullptr, TileSource* tiles = nullptr);

/// Same, seen through `camera` instead of the scene's own (the viewer's moving camera).
Image render(const Scene& scene, const Camera& camera, const LightSet& lights, const RenderPlan& plan,
             const accel::Accel& accel, const RenderSettings& settings, RenderStats* stats = nullptr);

/// Same, making the light set and the plan itself.
Image render(const Scene& scene, const accel::Accel& accel, const RenderSettings& settings,
             RenderStats* stats = nullptr);

/// The channel names of an image rendered with `layers`.
std::vector<std::string> channel_names(const Layers& layers);
/// The channel names of an image rendered with `plan`: those above, or `nodes` and `tris` (per-pixel
/// means over the samples) for the cost integrator.
std::vector<std::string> channel_names(const RenderPlan& plan);

}  // namespace arbor::engine
