#pragma once
/// The benchmark's command line, shared by `arbor_bench` and `arbor bench` (the same options and
/// reports; `arbor bench` also runs under mpirun, spreading the scenes over the ranks).
#include "perf/bench_run.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace arbor::perf {

struct BenchCommand;

/// Registers the benchmark's options on `app`; the returned command holds their values.
std::shared_ptr<BenchCommand> add_bench_options(CLI::App& app);

/// What a run of the command needs beyond its options.
struct BenchRunContext {
    std::string program = "arbor_bench";  ///< for messages and the report's command line
    std::string command;                  ///< the command line as typed
    SceneShare share;                     ///< where the scenes run (empty: all here)
    bool writes = true;                   ///< this process writes the report
    std::string on_ranks;                 ///< " on N ranks" for the summary line (MPI)
    int rank = -1;                        ///< the MPI rank, recorded in the rows (-1: none)
};

/// The options as a BenchOptions (throws engine::InputError on values that cannot run).
BenchOptions bench_options(const BenchCommand& c);
/// Runs the benchmark and writes the reports (when ctx.writes); returns the exit status.
int run_bench_command(const BenchCommand& c, const BenchRunContext& ctx);

}  // namespace arbor::perf
