#pragma once
/// The benchmark driver: for every scene of the plan, build every structure (and the Embree peer),
/// generate the ray kinds, FIRST validate every configuration (brute on a sample, the structure's
/// scalar path and Embree on all rays: the error columns), THEN time it (median of repeats with
/// min and max, the repeats of all configurations interleaved round-robin so that machine drift
/// hits them equally).
#include "perf/bench_options.h"
#include "perf/bench_result.h"

#include <functional>

namespace arbor::perf {

/// Spreads the scenes of a run over processes (`mpirun arbor bench`): calls `job(i)` for the
/// scenes [0, count) this process runs, and returns, on the process that writes the report,
/// every scene's part in plan order (elsewhere: nothing). Each scene runs wholly on one process,
/// so its rows' timings and its interleaved repeats stay those of one machine.
using SceneShare =
    std::function<std::vector<BenchResult>(std::size_t count, const std::function<BenchResult(std::size_t)>& job)>;

/// Runs the matrix of `o`. Progress lines go to stderr when o.verbose. Structures make_accel cannot
/// build, paths a structure lacks, and a missing Embree are skipped and listed in the notes.
/// Throws engine::InputError for bad options (unknown structure, scene or ray kind). With
/// `share`, the scenes run where it says (default: all here, in order) and a process that does
/// not write the report returns an empty result.
BenchResult run_bench(const BenchOptions& o, const SceneShare& share = {});

}  // namespace arbor::perf
