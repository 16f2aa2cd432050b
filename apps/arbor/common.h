#pragma once
/// Helpers shared by the subcommands: option validation, threads, scene loading, JSON output.
#include "accel/interface/accel.h"
#include "accel/select/auto_select.h"
#include "apps/arbor/program.h"
#include "engine/error.h"
#include "engine/scene.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <tbb/global_control.h>

namespace arbor::app {

/// A CLI11 check that runs `parse(value)` at parse time, so a bad value exits 2 before any file is
/// loaded; the OptionError's text (without the "OPTION: " that CLI11 adds itself) is the message.
template <class Parse> CLI::Validator parse_check(std::string option, Parse parse) {
    return CLI::Validator(
        [option, parse](std::string& v) -> std::string {
            try {
                (void)parse(v);
            } catch (const OptionError& e) {
                const std::string msg = e.what();
                return msg.rfind(option + ": ", 0) == 0 ? msg.substr(option.size() + 2) : msg;
            }
            return {};
        },
        "");
}

/// Adds `--accel NAME` (validated against the structure names) bound to `name`.
CLI::Option* add_accel_option(CLI::App& cmd, std::string& name);
/// Adds `--accel NAME[,NAME...]` (each validated) bound to `names` (`arbor render`: a list is for
/// the cost integrator's side-by-side images).
CLI::Option* add_accel_list_option(CLI::App& cmd, std::string& names);
/// The items of a comma-separated list ("a,b" -> {"a", "b"}; "" -> {""}).
std::vector<std::string> split_list(const std::string& s);
/// Adds the build settings shared by every command that builds a structure: `--leaf-size N`
/// (BvhBuildConfig::max_leaf_size; the seed report used 1), `--sah-bins N` (BvhBuildConfig::sah_bins),
/// `--max-memory BYTES` (BuildConfig::max_memory), `--simd-leaf-floor N`
/// (BvhBuildConfig::simd_leaf_floor), `--bvh-width 4|8|16` (WideConfig::width) and `--kd-walk
/// tight-cells|cells|ropes` (KdBlockConfig::walk).
void add_build_options(CLI::App& cmd, accel::BuildConfig& cfg);
/// Adds `--threads N` (N >= 1; default: all hardware threads).
CLI::Option* add_threads_option(CLI::App& cmd, int& threads);

/// Limits TBB to `threads` for the lifetime of the returned object (0 = all).
std::unique_ptr<tbb::global_control> limit_threads(int threads);
int active_threads();

/// Resolves an --accel name (accel::pick_accel): a named structure as is; `auto` decides for `job`
/// (accel/select/auto_select.h: the cost model, a probe when the job can pay for one).
accel::AccelPick resolve_accel(const std::string& name, const accel::AutoJob& job);
/// The same for a job auto knows nothing of but the triangles: 1M rays into the scene's bounds.
accel::AccelPick resolve_accel(const std::string& name, const accel::TriangleView& tris, const accel::BuildConfig& build = {});

/// Build statistics as JSON fields (nodes, leaves, max_depth, sah_cost, bytes_per_triangle, ...).
void put_stats(nlohmann::json& j, const accel::BuildStats& s);

}  // namespace arbor::app
