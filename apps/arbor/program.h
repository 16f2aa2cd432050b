#pragma once
/// What `arbor` and `arbor-bench` (perf/) share as programs, in the static library arbor_program:
/// the single error boundary of main(), the command line as typed, and (in cluster.h and
/// rank_guardian.h) the MPI job and the rank guardian. Bad input (InputError, option errors)
/// prints one line on stderr and exits 1 or 2 (spec/cli.md, "Errors"); nothing is caught anywhere
/// else. Under mpirun the line comes from rank 0 only, naming the rank that failed, and the whole
/// job stops (apps/arbor/cluster.h).
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "engine/error.h"

namespace arbor::app {

/// A bad option value found by arbor's own checks (exit 2, as CLI11's parse errors; spec/cli.md).
/// Its message starts with the option's name.
struct OptionError : engine::InputError {
    using engine::InputError::InputError;
};

/// The command line as typed, "arbor SUBCOMMAND ..." (for reports); main() sets it.
inline std::string& command_line() {
    static std::string line;
    return line;
}

/// The program's name in its one-line messages ("arbor" or "arbor-bench"); main() sets it.
inline std::string& program_name() {
    static std::string name = "arbor";
    return name;
}

/// Prints "<program>: <what>" and returns `code`; in an MPI job, stops the whole job instead (rank
/// 0 prints the line with the failing rank). Before a job is joined (option errors), only the
/// launcher's rank 0 prints, so that N ranks do not print N copies.
int failure(int code, const std::string& what);

/// The error boundary: runs `parse_and_run` (which parses `app` and runs the chosen command) and
/// turns every exception into its exit status (help and version: 0; CLI11 parse errors and
/// OptionError: 2; InputError: 1; out of memory: 3; anything else: 4). After the command, a
/// joined MPI job is left (a failing status on one rank stops every rank).
int run_guarded(CLI::App& app, const std::function<int()>& parse_and_run);

}  // namespace arbor::app
