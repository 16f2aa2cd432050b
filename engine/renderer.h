#pragma once
/// Tile renderer: TBB over 16x16 tiles; each tile traces its rays as batches through the Accel
/// (primary, then shadow, then mirror bounces), so the structure picks its fastest path per batch.
/// Random numbers depend only on (pixel, sample, dimension): the image is the same for any
/// number of threads.
#include "accel/accel.h"
#include "engine/image.h"
#include "engine/scene.h"

#include <atomic>
#include <cstdint>

namespace arbor::engine {

struct RenderSettings {
    int width = 640, height = 480;
    int spp = 4;          ///< samples per pixel, stratified jitter
    int max_depth = 3;    ///< mirror bounces
    int tile = 16;
    bool progress = false;  ///< a progress line on stderr
};

/// Rays traced, by kind; and what the plan left out.
struct RenderStats {
    double seconds = 0.0;
    std::uint64_t primary = 0, shadow = 0, bounce = 0;
    std::uint64_t total() const { return primary + shadow + bounce; }
};

/// Renders `scene` with `accel` (built over scene.mesh) into channels R, G, B.
Image render(const Scene& scene, const accel::Accel& accel, const RenderSettings& settings, RenderStats* stats = nullptr);

}  // namespace arbor::engine
