#pragma once
/// `arbor render --integrator cost` (spec/cli.md): the nodes visited and triangles tested by every
/// camera ray, for one structure or several side by side.
#include "accel/interface/build_config.h"
#include "apps/arbor/render_options.h"
#include "apps/arbor/scene_options.h"

#include <string>

namespace arbor::app {

struct CostRenderOptions {
    const SceneOptions& scene;
    const RenderOptions& render;
    const std::string& accels;  ///< NAME[,NAME...]
    const accel::BuildConfig& build;
    const std::string& out;     ///< .png: the picture only; otherwise EXR (layers nodes, tris) + PNG beside
    bool no_png = false, verbose = false, quiet = false;
};

/// Renders, writes the outputs and prints a line per structure; returns the exit status.
int run_cost_render(const CostRenderOptions& o);

}  // namespace arbor::app
