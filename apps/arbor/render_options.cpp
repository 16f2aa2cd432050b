#include "apps/arbor/render_options.h"

#include "apps/arbor/common.h"
#include "engine/error.h"

namespace arbor::app {

void add_render_options(CLI::App& cmd, RenderOptions& o, bool converge) {
    cmd.add_option("--width", o.width, "image width")->check(CLI::Range(1, 1 << 15))->capture_default_str();
    cmd.add_option("--height", o.height, "image height")->check(CLI::Range(1, 1 << 15))->capture_default_str();
    if (!converge) {
        cmd.add_option("--spp", o.spp, "samples per pixel (stratified jitter)")->check(CLI::Range(1, 1 << 16))->capture_default_str();
        cmd.add_option("--integrator", o.integrator, "primary, ao, direct, path or cost")
            ->check(parse_check("--integrator", parse_integrator_option))
            ->capture_default_str();
    }
    cmd.add_option("--depth", o.depth, "bounces after the camera ray (default: 3 for direct, 8 for path)")
        ->check(CLI::Range(0, 64));
    cmd.add_option("--layers", o.layers,
                   "extra EXR layers: none or a list of z,n,a (depth, normal, albedo; default: all for primary)")
        ->check(parse_check("--layers", parse_layers));
    cmd.add_option("--ao-samples", o.ao_samples, "AO rays per camera sample")->check(CLI::Range(1, 1024))->capture_default_str();
    cmd.add_option("--ao-radius", o.ao_radius, "AO ray length (default: 1/4 of the scene's diagonal)")
        ->check(CLI::Range(0.0f, 1e30f));
    cmd.add_option("--tile", o.tile, "tile edge in pixels")->check(CLI::Range(1, 1024))->capture_default_str();
    cmd.add_option("--seed", o.seed, "random seed (selects independent sample streams)")->capture_default_str();
}

engine::IntegratorKind parse_integrator_option(const std::string& name) {
    const auto k = engine::parse_integrator(name);
    if (!k)
        throw OptionError("--integrator: unknown integrator '" + name + "' (expected one of " +
                                 engine::integrator_names() + ")");
    return *k;
}

engine::Layers parse_layers(const std::string& list) {
    engine::Layers l;
    if (list == "none") return l;
    std::size_t b = 0;
    while (true) {
        const std::size_t e = list.find(',', b);
        const std::string p = list.substr(b, e == std::string::npos ? std::string::npos : e - b);
        if (p == "z") l.depth = true;
        else if (p == "n") l.normal = true;
        else if (p == "a") l.albedo = true;
        else throw OptionError("--layers: unknown layer '" + p + "' (expected none or a list of z, n, a)");
        if (e == std::string::npos) return l;
        b = e + 1;
    }
}

engine::RenderSettings to_settings(const RenderOptions& o, engine::IntegratorKind integrator) {
    engine::RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.spp = o.spp;
    s.integrator = integrator;
    s.max_depth = o.depth;
    s.ao_samples = o.ao_samples;
    s.ao_radius = o.ao_radius;
    s.tile = o.tile;
    s.seed = o.seed;
    if (!o.layers.empty()) s.layers = parse_layers(o.layers);
    return s;
}

}  // namespace arbor::app
