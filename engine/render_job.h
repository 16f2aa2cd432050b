#pragma once
/// The rays a render traces, described for `--accel auto` (accel/select/auto_select.h) before
/// anything is built, so that `arbor render`, `arbor converge` and the cost render ask the one
/// decision about their actual ray mix: camera rays (a sample of them, from the scene's camera in
/// tile order), shadow rays to the lights, and bounces (mirror, diffuse, AO), each with the hint
/// the renderer gives its batches (engine/tracer.h: camera and shadow rays coherent, bounces not).
///
/// Counts per sample are estimates from the plan (a ray that misses the scene spawns nothing, which
/// the plan cannot know, so every camera ray is assumed to hit): shadow rays one per point light
/// and one for area lights at each path vertex; mirror rays one per sample (plus the bounces of
/// `path`); diffuse bounces min(depth, Russian-roulette depth + 1); AO ao_samples per sample.
#include "accel/select/auto_select.h"
#include "engine/plan.h"
#include "engine/scene.h"

#include <vector>

namespace arbor::engine {

struct RenderRays {
    std::vector<accel::Ray> camera_sample;  ///< owned here; groups[0].sample points into it
    std::vector<accel::RayGroup> groups;
};

/// The rays of `renders` renders of `plan` at `set`'s size (renders may be fractional: converge
/// sums several sample counts into one plan of 1 spp times their total).
RenderRays render_rays(const Scene& scene, const RenderPlan& plan, const RenderSettings& set, double renders = 1.0);

/// The whole auto job of a render: the scene's triangles, the rays above, the build settings.
/// `rays` must outlive the job (the camera group's sample points into it).
accel::AutoJob render_job(const Scene& scene, const RenderRays& rays, const accel::BuildConfig& build);

}  // namespace arbor::engine
