#include "perf/bench_plan.h"

#include "engine/error.h"
#include "engine/log.h"
#include "engine/obj_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

namespace arbor::perf {

std::vector<std::string> model_files(const std::string& models_dir) {
    std::vector<std::string> out;
    std::error_code ec;
    if (models_dir.empty() || !std::filesystem::is_directory(models_dir, ec)) return out;
    for (const auto& e : std::filesystem::directory_iterator(models_dir, ec))
        if (e.path().extension() == ".obj") out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

BenchOptions BenchOptions::quick() {
    BenchOptions o;
    o.scenes = {"tiny", "?teapot", "?stanford-bunny", "stadium", "interior", "grass", "soup", "scaling"};
    o.scaling_max_exp = 5;
    o.grass_blades = 20000;
    o.soup_triangles = 20000;
    o.interior_detail = 1;
    o.rays = std::size_t(1) << 13;
    o.scaling_rays = std::size_t(1) << 13;
    o.repeats = 3;
    o.kind_seconds = 1.0;
    o.min_timed_ms = 4.0;
    o.min_timed_rays = std::size_t(1) << 12;
    o.build_repeats = 2;
    o.brute_budget = 2e8;
    o.max_sample = 256;
    o.count_sample = 1024;
    o.embree_variants = false;
    return o;
}

std::vector<SceneSource> plan_scenes(const BenchOptions& o) {
    std::vector<SceneSource> out;
    auto add = [&](SceneSource s) {
        if (std::none_of(out.begin(), out.end(), [&](const SceneSource& x) { return x.name == s.name; }))
            out.push_back(std::move(s));
    };
    const std::vector<std::string> models = model_files(o.models_dir);
    auto model_path = [&](const std::string& stem) -> std::string {
        for (const auto& m : models)
            if (std::filesystem::path(m).stem() == stem) return m;
        return {};
    };
    auto add_replicated = [&](int k) {
        const auto n = std::size_t(std::llround(std::pow(10.0, k)));
        add({"replicated-1e" + std::to_string(k), "replicated", [n] { return replicated(n); }});
    };
    for (std::string name : o.scenes) {
        const bool optional = !name.empty() && name[0] == '?';
        if (optional) name.erase(0, 1);
        if (name == "all" || name == "models") {
            for (const auto& m : models) add({std::filesystem::path(m).stem().string(), "model", [m] { return model_scene(m); }});
        }
        if (name == "all" || name == "stadium") {
            const std::string teapot = model_path("teapot");
            add({"stadium", "stadium", [teapot] {
                     if (teapot.empty()) return teapot_in_stadium(nullptr);
                     engine::Warnings w;
                     const engine::Mesh model = engine::load_obj(teapot, w);
                     return teapot_in_stadium(&model);
                 }});
        }
        if (name == "all" || name == "interior") add({"interior", "interior", [d = o.interior_detail] { return architectural_interior(d); }});
        if (name == "all" || name == "grass") add({"grass", "grass", [n = o.grass_blades] { return grass_field(n); }});
        if (name == "all" || name == "soup") add({"soup", "soup", [n = o.soup_triangles] { return triangle_soup(n); }});
        if (name == "all" || name == "scaling")
            for (int k = 3; k <= std::clamp(o.scaling_max_exp, 3, 7); ++k) add_replicated(k);
        if (name == "tiny") add({"tiny", "tiny", [] { return tiny_scene(); }});
        const bool known = name == "all" || name == "models" || name == "stadium" || name == "interior" ||
                           name == "grass" || name == "soup" || name == "scaling" || name == "tiny";
        if (known) continue;
        if (name.rfind("replicated-1e", 0) == 0 && name.size() == 14 && name[13] >= '3' && name[13] <= '7') {
            add_replicated(name[13] - '0');
            continue;
        }
        const std::string path = model_path(name);
        if (path.empty() && optional) continue;
        if (path.empty())
            throw engine::InputError("--scenes: unknown scene '" + name +
                                     "' (expected all, models, stadium, interior, grass, soup, scaling, tiny, "
                                     "replicated-1e3..7, or a model in '" + o.models_dir + "')");
        add({name, "model", [path] { return model_scene(path); }});
    }
    return out;
}

}  // namespace arbor::perf
