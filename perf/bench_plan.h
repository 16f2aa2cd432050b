#pragma once
/// Turns BenchOptions into the list of scenes to run, each made only when its turn comes (so a
/// 10^7-triangle scene is never in memory beside another big one).
#include "perf/bench_options.h"
#include "perf/scenes.h"

#include <functional>
#include <string>
#include <vector>

namespace arbor::perf {

struct SceneSource {
    std::string name;
    std::string family;
    std::function<BenchScene()> make;
};

/// The scenes of `o.scenes`, in order, without duplicates. Throws engine::InputError naming
/// --scenes for an unknown name, and for a model name when its file is missing.
std::vector<SceneSource> plan_scenes(const BenchOptions& o);

/// Paths of models_dir/*.obj, sorted; empty when the folder is missing or empty.
std::vector<std::string> model_files(const std::string& models_dir);

}  // namespace arbor::perf
