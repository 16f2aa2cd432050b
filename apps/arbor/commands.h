#pragma once
/// The subcommands of `arbor` (spec/cli.md). Each registers its options on the CLI11 app and
/// returns the function that runs it; main() owns parsing and the single error boundary.
#include "apps/arbor/program.h"

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace arbor::app {

using Run = std::function<int()>;

Run add_info(CLI::App& app);
Run add_trace(CLI::App& app);
Run add_render(CLI::App& app);
Run add_rays(CLI::App& app);
Run add_converge(CLI::App& app);
Run add_stress(CLI::App& app);
Run add_view(CLI::App& app);

}  // namespace arbor::app
