#pragma once
/// The rendering options shared by `arbor render` and `arbor converge`.
#include "engine/render_settings.h"

#include <CLI/CLI.hpp>

#include <string>

namespace arbor::app {

struct RenderOptions {
    int width = 640, height = 480, spp = 4, depth = -1, ao_samples = 4, tile = 16;
    float ao_radius = -1.0f;
    std::string integrator = "direct";
    std::string layers;  ///< "" (the integrator's default), "none", or a comma list of z, n, a
    std::uint32_t seed = 0;
};

/// Registers --width --height --depth --layers --ao-samples --ao-radius --tile --seed, and
/// --spp and --integrator unless `converge` (which has its own lists).
void add_render_options(CLI::App& cmd, RenderOptions& o, bool converge);

/// Settings for integrator `integrator` (already validated); OptionError naming --layers on a bad list.
engine::RenderSettings to_settings(const RenderOptions& o, engine::IntegratorKind integrator);

/// Parses --integrator NAME (one-line OptionError naming the option otherwise: exit 2).
engine::IntegratorKind parse_integrator_option(const std::string& name);
/// Parses --layers: "none" or a comma list of z, n, a (OptionError otherwise).
engine::Layers parse_layers(const std::string& list);

}  // namespace arbor::app
