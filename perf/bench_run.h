#pragma once
/// The benchmark driver: for every scene of the plan, build every structure (and the Embree peer),
/// generate the ray kinds, FIRST validate every configuration (brute on a sample, the structure's
/// scalar path and Embree on all rays: the error columns), THEN time it (median of repeats with
/// min and max, the repeats of all configurations interleaved round-robin so that machine drift
/// hits them equally).
#include "perf/bench_options.h"
#include "perf/bench_result.h"

namespace arbor::perf {

/// Runs the matrix of `o`. Progress lines go to stderr when o.verbose. Structures make_accel cannot
/// build, paths a structure lacks, and a missing Embree are skipped and listed in the notes.
/// Throws engine::InputError for bad options (unknown structure, scene or ray kind).
BenchResult run_bench(const BenchOptions& o);

}  // namespace arbor::perf
