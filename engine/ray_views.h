#pragma once
/// Camera and light placements drawn from a seed, for evaluation rays the benchmark was never
/// tuned on (`arbor rays --view-seed S`, scripts/bench_heldout.sh). The benchmark's own rays
/// (engine/ray_gen.h) always use one camera, front-right-above at 2.5 radii, and one light; a held-out
/// view moves both, so that a speed figure measured on it says something about rays in general.
#include "engine/ray_gen.h"
#include "engine/scene.h"

#include <cstdint>

namespace arbor::engine {

/// Places the camera and the light of `gen` (made by ray_gen_scene from `scene`) from `seed`; the
/// same seed gives the same placement on any machine.
///   - Scenes without a camera of their own (models; `own_camera` false): the camera orbits the
///     bounding sphere at a uniformly random direction (below the model too), 1.6-3.5 radii from
///     the centre, aimed within 0.15 radii of the centre, its image covering 55-100% of the width
///     of the sphere's disk (near and zoomed views send most rays onto the model); the light sits
///     at a uniform direction of the camera's hemisphere, 1.5-4 radii out, drawn again while less
///     than a fifth of the surface area has camera and light on the same side (flat models).
///   - Scenes with their own camera (builtin scenes, `own_camera` true, gen.camera set): that camera
///     moved by up to 10% of its distance to its target, the target by up to 5%, and the scene's
///     first light moved by up to 10% of the bounds' size, or, when the scene has no point light
///     (the Cornell box's area light), a light at a random point of the middle 60% of the bounds.
void place_seeded_view(RayGenScene& gen, const Scene& scene, std::uint64_t seed, bool own_camera);

}  // namespace arbor::engine
