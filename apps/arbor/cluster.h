#pragma once
/// This process's part in an MPI job: `mpirun -np N arbor render|converge|bench ...` (spec/cli.md,
/// "Across machines"). Every rank runs the same command; rank 0 writes the outputs and prints,
/// the other ranks' standard output goes to /dev/null. Joining loads the module arbor_mpi.so
/// (mpi/job.h) and initialises MPI; a plain call (no launcher in the environment, no --mpi) joins
/// nothing and loads nothing.
#include "engine/render_settings.h"
#include "engine/scene.h"
#include "engine/tile_source.h"
#include "mpi/job.h"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <memory>
#include <string>

namespace arbor::app {

class Cluster {
public:
    /// Joins the job when a launcher started this process (mpi/launcher.h) or `force` (--mpi);
    /// nullptr otherwise. Throws InputError when MPI is wanted but the module cannot be loaded
    /// (an arbor built without MPI, a missing arbor_mpi.so). The cluster lives until leave().
    static Cluster* join(bool force);
    /// The joined cluster, if any.
    static Cluster* current();
    /// Every rank waits for the others, then MPI is finalised (main() calls it after a command).
    static void leave();

    int rank() const { return job_->rank(); }
    int size() const { return job_->size(); }
    bool root() const { return job_->rank() == 0; }
    mpi::Job& job() { return *job_; }
    /// " on N ranks" for a summary line.
    std::string on_ranks() const;

    /// Refuses ranks that loaded another scene (engine::scene_hash) or were given other settings
    /// (`settings`: a text naming every setting that changes the result) than rank 0.
    void require_same(const engine::Scene& scene, const std::string& settings);
    /// Rank 0's `value` on every rank (e.g. what --accel auto picked there).
    std::string root_choice(const std::string& value);
    /// The tiles of one frame spread over the ranks (apps/arbor/cluster_tiles.cpp).
    std::unique_ptr<engine::TileSource> frame_tiles();

    /// Stops the job: rank 0 prints "arbor: rank R: <what>", every process exits with `code`.
    [[noreturn]] void fail(int code, const std::string& what) {
        job_->fail(code, what);
        std::abort();  // not reached: Job::fail does not return
    }

private:
    explicit Cluster(mpi::Job* job) : job_(job) {}
    std::unique_ptr<mpi::Job> job_;
};

/// Adds `--mpi` (join an MPI job even when no launcher variable is set) bound to `flag`.
void add_mpi_option(CLI::App& cmd, bool& flag);
/// A text of the settings that change a rendered image, for Cluster::require_same.
std::string settings_text(const engine::RenderSettings& s);

/// Test-only fault injection (ARBOR_MPI_TEST_FAULT=RANK:TILES:KIND, KIND one of abort, segv,
/// kill, term, term-guardian, throw, oom, stop (SIGSTOP), interrupt (SIGINT to mpirun),
/// kill-guardian): rank RANK fails that way after finishing TILES tiles. Read once.
void inject_test_fault(int rank, long tiles_done);

}  // namespace arbor::app
