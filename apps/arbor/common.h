#pragma once
/// Helpers shared by the subcommands: option validation, threads, scene loading, JSON output.
#include "accel/accel.h"
#include "accel/select/auto_select.h"
#include "engine/scene.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <string>

#include <tbb/global_control.h>

namespace arbor::app {

/// Adds `--accel NAME` (validated against the structure names) bound to `name`.
CLI::Option* add_accel_option(CLI::App& cmd, std::string& name);
/// Adds the build settings shared by every command that builds a structure: `--leaf-size N`
/// (BuildConfig::max_leaf_size; the seed report used 1), `--sah-bins N` (BuildConfig::sah_bins) and
/// `--bvh-width 4|8|16` (BuildConfig::bvh_width).
void add_build_options(CLI::App& cmd, accel::BuildConfig& cfg);
/// Adds `--threads N` (N >= 1; default: all hardware threads).
CLI::Option* add_threads_option(CLI::App& cmd, int& threads);

/// Limits TBB to `threads` for the lifetime of the returned object (0 = all).
std::unique_ptr<tbb::global_control> limit_threads(int threads);
int active_threads();

/// Resolves an --accel name (accel::pick_accel): a named structure as is; `auto` calibrates on
/// `work` and picks the structure with the smallest predicted build + trace time.
accel::AccelPick resolve_accel(const std::string& name, const accel::TriangleView& tris, const accel::AutoWork& work = {});

/// Build statistics as JSON fields (nodes, leaves, max_depth, sah_cost, bytes_per_triangle, ...).
void put_stats(nlohmann::json& j, const accel::BuildStats& s);

}  // namespace arbor::app
