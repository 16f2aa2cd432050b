/// Liveness of the job's ranks, on the service thread of each (mpi/job_mpi.h).
///
/// Heartbeat: rank 0 watches every other rank, and every other rank watches rank 0. Any message
/// counts as a sign of life; a rank that sent nothing to a watcher for a beat (1 s) sends it an
/// empty one, so a busy render adds almost no messages. A watcher that heard nothing from a rank
/// for the deadline (5 s; $ARBOR_MPI_HEARTBEAT changes it) prints one line naming that rank and
/// stops the job with exit status 4: the rank was stopped (SIGSTOP, Ctrl-Z on its machine),
/// hangs where its service thread cannot run, or is cut off. Rank 1 watches rank 0 with the
/// deadline, ranks above it with twice the deadline, so that a silent rank 0 is named once.
/// A process that itself did not run for a while (stopped, then resumed) gives its peers a new
/// deadline instead of blaming them.
///
/// Launcher stop: mpirun stops every rank with SIGTERM both when a rank failed (which that rank
/// or its guardian has already reported) and when mpirun itself was interrupted (Ctrl-C, or
/// SIGINT, SIGTERM or SIGHUP sent to it), and then exits 1 whatever the ranks do. Every rank the
/// launcher stops tells rank 0 before it quits; rank 0 prints the interrupt line only when all of
/// them did, since a failed rank is silent.
#include "mpi/job_mpi.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace arbor::mpi::detail {

namespace {

/// A gap this long between two turns of the service thread means this process did not run.
constexpr double stall_seconds = 1.0;
/// How long rank 0 waits for the other ranks to say that the launcher stops them. mpirun sends
/// SIGKILL about 1 s after its SIGTERM.
constexpr double verdict_seconds = 0.8;
/// How long a rank the launcher stops lives on after its word to rank 0, so that rank 0 decides
/// first (mpirun sends SIGKILL about 1 s after its SIGTERM).
constexpr double goodbye_seconds = 0.5;

}  // namespace

Heartbeat Heartbeat::from_environment() {
    Heartbeat h;
    if (const char* v = std::getenv("ARBOR_MPI_HEARTBEAT"); v && *v) {
        char* end = nullptr;
        const double deadline = std::strtod(v, &end);
        if (end != v && *end == '\0' && deadline >= 0.5 && deadline <= 86400.0) {
            h.deadline = deadline;
            h.beat = deadline / 5.0;
        }
    }
    return h;
}

void MpiJob::keep_alive(double now) {
    if (size_ == 1 || finished_) return;
    if (now - last_turn_ > stall_seconds)
        for (double& t : heard_) t = std::max(t, now);
    last_turn_ = now;
    auto beat = [&](int peer) {
        if (now - sent_[std::size_t(peer)] < heartbeat_.beat) return;
        // Fire and forget: an empty message needs no buffer, and a peer that is gone must not
        // keep this thread waiting for the send to complete.
        static char none = 0;
        MPI_Request r;
        MPI_Isend(&none, 0, MPI_BYTE, peer, tag_heartbeat, comm_, &r);
        MPI_Request_free(&r);
        sent_[std::size_t(peer)] = now;
    };
    if (rank_ == 0) {
        for (int r = 1; r < size_; ++r) beat(r);
    } else {
        beat(0);
    }
    if (fatal_sent_ || launcher_stop_since_ > 0.0) return;  // the job is being stopped already
    auto silent = [&](int r, double limit) {
        const double quiet = now - heard_[std::size_t(r)];
        if (quiet <= limit) return;
        char line[512];
        std::snprintf(line, sizeof line,
                      "arbor: %s has not answered for %.0f s (stopped, hung, or cut off from rank %d); the job stops",
                      describe_rank(r).c_str(), quiet, rank_);
        end_job(4, line);
    };
    if (rank_ == 0) {
        for (int r = 1; r < size_; ++r) silent(r, heartbeat_.deadline);
    } else {
        silent(0, rank_ == 1 ? heartbeat_.deadline : 2.0 * heartbeat_.deadline);
    }
}

void MpiJob::on_launcher_stop(double now) {
    const bool first = launcher_stop_since_ == 0.0;
    if (first) launcher_stop_since_ = now;
    if (rank_ != 0) {
        if (first) {
            static char none = 0;
            MPI_Isend(&none, 0, MPI_BYTE, 0, tag_stopping, comm_, &stopping_request_);
        }
        int sent = 0;
        MPI_Test(&stopping_request_, &sent, MPI_STATUS_IGNORE);
        // Not at once: when this rank quit at once, rank 0 was ended before it had read the word in
        // 1 run in 5, presumably by Open MPI's handling of a rank that ends.
        if (now - launcher_stop_since_ > goodbye_seconds) quit_quietly();
        return;
    }
    int stopping = 0;
    for (int r = 1; r < size_; ++r) stopping += stopping_from_[std::size_t(r)];
    if (stopping == size_ - 1) {
        std::fprintf(stderr,
                     "arbor: interrupted: mpirun stopped the job (Ctrl-C, or SIGINT, SIGTERM or SIGHUP sent to "
                     "mpirun) while all %d rank%s ran; rank 0 wrote nothing\n",
                     size_, size_ == 1 ? "" : "s");
        std::fflush(stderr);
        quit_quietly();
    }
    if (now - launcher_stop_since_ > verdict_seconds) quit_quietly();
}

}  // namespace arbor::mpi::detail
