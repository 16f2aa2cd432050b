#pragma once
/// Under an MPI launcher each rank is two processes: the one the launcher started stays a small
/// guardian that only waits, and its child (forked at the top of main(), before any thread
/// exists) is the rank that loads, renders and speaks MPI. Why: a process killed by a signal that
/// cannot be caught (SIGKILL: `kill -9`, or the out-of-memory killer, which picks the process
/// holding the scene) makes mpirun exit 128 + 9 = 137 whatever the other ranks do, and a status
/// above 127 reads as "killed by a signal" (spec/cli.md: a defect). The guardian sees its rank
/// die, prints one line naming the rank and the signal, and exits 4, which mpirun then returns.
/// Signals sent to the guardian are passed on to the rank, marked with their sender (0: the
/// launcher), so that the rank tells mpirun stopping the job from a user's `kill`
/// (mpi/faults_mpi.cpp). When the guardian dies (SIGKILL), the rank gets a signal
/// (PR_SET_PDEATHSIG, mpi::guardian_lost_signal()): it ends the rank, or once MPI is up, has the
/// rank report its guardian's death and stop the job. A plain call (no launcher in the
/// environment) forks nothing.
namespace arbor::app {

/// Returns in the rank, or at once when no launcher started this process; in the guardian it
/// never returns: it waits for the rank and exits with its status.
void guard_rank();

}  // namespace arbor::app
