#pragma once
/// The probe of `--accel auto` (auto_select.h, step 3): builds a few structures whole and times a
/// sample of the job's rays on each of the configurations it is asked about. Each timing traces the
/// sample on the calling thread and reads that thread's CPU clock, divided by the job's threads:
/// neither the time other processes hold the core (this machine is shared) nor TBB workers'
/// idle spinning around a short parallel loop counts (a parallel timing of a few thousand rays was
/// mostly the latter on a loaded machine, and ranked packets and single rays unlike the full run).
/// The smallest of `rounds` rounds run over all configurations in turn, so that a burst of other
/// work does not hit one configuration alone.
/// Builds are timed by the wall clock (the job pays them so).
#include "accel/interface/accel.h"

#include <memory>
#include <span>
#include <vector>

namespace arbor::accel {

struct ProbeGroup {
    std::span<const Ray> rays;  ///< the sample (already cut to the probe's size)
    Query query = Query::closest;
};

struct ProbeConfig {
    std::size_t structure = 0;            ///< index into the probe's structures
    std::vector<TracePath> group_paths;   ///< the path of each group (scalar, packet or single)
};

struct ProbeResult {
    std::vector<std::unique_ptr<Accel>> built;  ///< per structure
    std::vector<double> build_ms;               ///< per structure, wall
    /// ns per ray, per configuration and group (CPU time / threads, fastest round).
    std::vector<std::vector<double>> ns;
};

/// Builds `structures` over `tris` with `cfg` (in that order) and times every configuration on
/// every group: each timing traces its group's sample once on the calling thread, and again until
/// `min_timing_ms` of wall time have passed. `threads` divides the thread's CPU time.
ProbeResult run_probe(const TriangleView& tris, const BuildConfig& cfg, const std::vector<AccelKind>& structures,
                      const std::vector<ProbeConfig>& configs, const std::vector<ProbeGroup>& groups, int rounds,
                      double min_timing_ms, double threads);

/// CPU time of the whole process, ms (all threads).
double process_cpu_ms();
/// CPU time of the calling thread, ms.
double thread_cpu_ms();

}  // namespace arbor::accel
