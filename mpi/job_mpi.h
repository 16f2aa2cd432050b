#pragma once
/// Inside the module arbor_mpi.so: the Job of mpi/job.h over MPI. One service thread initialises
/// MPI, makes every MPI call (MPI_THREAD_FUNNELED: it is MPI's main thread), and finalises it.
/// It never blocks in MPI: collectives are nonblocking (MPI-3) and tested in its loop, messages
/// are probed, so it always notices a failing rank, a crash signal or mpirun's SIGTERM within a
/// millisecond. It also keeps a heartbeat (mpi/liveness_mpi.cpp): rank 0 and the other ranks
/// watch each other's messages and stop the job when one falls silent. Application threads hand
/// it work with post() and wait for the answers.
#include "mpi/job.h"

#include <mpi.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <list>
#include <mutex>
#include <thread>

namespace arbor::mpi::detail {

enum Tag : int {
    tag_request = 11,
    tag_grant = 12,
    tag_result = 13,
    tag_fatal = 14,
    tag_heartbeat = 15,  ///< empty: "still here", sent when nothing else went to that rank lately
    tag_stopping = 16,   ///< empty, to rank 0: "the launcher is stopping me" (mpirun interrupted)
};

/// The heartbeat's timing. A rank that sent nothing to a watcher for `beat` seconds sends an
/// empty message; a watcher that heard nothing from a rank for `deadline` seconds stops the job.
struct Heartbeat {
    double beat = 1.0;
    double deadline = 5.0;
    /// $ARBOR_MPI_HEARTBEAT (seconds, the deadline; the beat is a fifth of it), else the defaults.
    static Heartbeat from_environment();
};

class FarmImpl;

class MpiJob final : public Job {
public:
    MpiJob();  ///< starts the service thread; throws std::runtime_error when MPI does not start
    ~MpiJob() override;

    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::string host() const override { return hosts_[std::size_t(rank_)]; }
    int node_rank() const override { return node_rank_; }
    int nodes() const override { return nodes_; }

    void require_same(const std::string& what, std::uint64_t value, const std::string& advice) override;
    std::string broadcast(const std::string& bytes) override;
    std::vector<double> sum(const std::vector<double>& values) override;
    std::unique_ptr<Farm> farm(const FarmSpec& spec, FarmResult on_result) override;
    [[noreturn]] void fail(int code, const std::string& what) override;
    void set_cleanup(std::function<void()> cleanup) override;

    // --- for the farm and the fault handling (mpi/farm_mpi.cpp, mpi/faults_mpi.cpp) ---
    /// Runs `f` on the service thread at its next turn.
    void post(std::function<void()> f);
    /// Wakes the service thread now (e.g. a farm's queue ran low).
    void kick();
    /// Service thread: calls `then` on the service thread once `request` completes. `urgent`: an
    /// application thread waits for it (a collective), so the loop keeps its shortest pause (MPI
    /// progresses nonblocking collectives only inside MPI calls).
    void watch(MPI_Request request, std::function<void()> then, bool urgent = true);
    /// Service thread: sends `bytes` to `dest` without blocking; the buffer lives until sent.
    void send(int dest, int tag, std::string bytes, std::function<void()> then = {});
    MPI_Comm comm() const { return comm_; }
    /// Runs `start` on the service thread, which calls the completion it is given when done; the
    /// calling (application) thread waits for that.
    void call(const std::function<void(std::function<void()> done)>& start);
    /// Service thread: stops the job from this rank (prints on rank 0, forwards elsewhere).
    void stop_job(int code, const std::string& what);
    /// "rank R (pid P on HOST)".
    std::string describe_rank(int r) const;
    /// Service thread: prints `line` (a whole "arbor: ..." line), runs the cleanup and ends the
    /// job with `code` (MPI_Abort).
    [[noreturn]] void end_job(int code, const std::string& line);
    /// Service thread: the launcher is stopping the job; this process ends without a word.
    [[noreturn]] void quit_quietly();
    bool service_thread() const { return std::this_thread::get_id() == service_.get_id(); }

private:
    void loop(std::promise<void>& started);
    /// One turn of the service loop. Returns 2 when a message arrived or an urgent request is
    /// pending (keep polling fast), 1 when only local work was done, 0 when idle.
    int step();
    bool poll_messages();  ///< receives and dispatches every waiting message
    void on_fatal(const MPI_Status& st);
    void check_signals(double now);
    /// mpi/liveness_mpi.cpp: sends heartbeats that are due and stops the job when a watched rank
    /// has been silent past the deadline.
    void keep_alive(double now);
    /// mpi/liveness_mpi.cpp: the launcher stops the job. Rank 0 prints one line when every other
    /// rank says it is being stopped too (nobody failed: mpirun was interrupted), and nothing when
    /// one is silent (its failure, reported by itself or its guardian, is why).
    void on_launcher_stop(double now);

    std::thread service_;
    int rank_ = 0, size_ = 1, node_rank_ = 0, nodes_ = 1;
    MPI_Comm comm_ = MPI_COMM_NULL;
    std::vector<std::string> hosts_;
    std::vector<long> pids_;

    std::mutex mu_;  ///< guards posted_, kicked_, stopping_
    std::condition_variable wake_;
    std::deque<std::function<void()>> posted_;
    bool kicked_ = false, stopping_ = false;

    struct Watched {
        MPI_Request request;
        std::function<void()> then;
        bool urgent;
    };
    std::vector<Watched> watched_;  ///< service thread only
    std::list<std::string> sending_;  ///< buffers of sends in flight (service thread only)

    std::atomic<bool> fatal_sent_{false};
    bool crash_reported_ = false, stop_reported_ = false, guardian_reported_ = false;
    std::function<void()> cleanup_;  ///< set before the first farm; run on the service thread

    // Liveness (service thread only).
    Heartbeat heartbeat_;
    std::vector<double> heard_, sent_;  ///< per rank: when the last message came from / went to it
    double last_turn_ = 0.0;            ///< when this thread's previous turn ran
    bool finished_ = false;             ///< past the final barrier: no more watching
    double launcher_stop_since_ = 0.0;  ///< when this rank saw the launcher stopping the job
    MPI_Request stopping_request_ = MPI_REQUEST_NULL;
    std::vector<char> stopping_from_;   ///< rank 0: which ranks said the launcher stops them
    double fatal_deadline_ = 0.0;  ///< a non-zero rank that reported a failure stops itself then
    int fatal_code_ = 1;
    std::string fatal_what_;

    friend class FarmImpl;
    FarmImpl* farm_ = nullptr;           ///< the active farm (service thread only)
    std::uint32_t farms_started_ = 0;    ///< farms created (every rank counts alike)
    std::vector<std::pair<int, std::string>> early_requests_;  ///< rank 0: requests for a farm not started yet
};

/// Signals (mpi/faults_mpi.cpp): crash signals are held until the service thread has reported
/// them to rank 0; SIGTERM, SIGINT and SIGHUP are noted for the service thread with their sender.
void install_signal_handlers();  ///< on the service thread
/// The crash signal caught (0: none).
int caught_crash_signal();
/// The first stop signal not sent by the launcher (0: none), and its sender's pid (-1: unknown).
int caught_stop_signal();
long stop_signal_sender();
/// Whether the launcher (mpirun, directly or through the rank's guardian) sent a stop signal.
bool stopped_by_launcher();
/// Whether this rank's guardian (apps/arbor/rank_guardian.h) died, and its process id (0: none).
bool guardian_lost();
long guardian_process();
/// "SIGSEGV (segmentation fault)".
std::string signal_text(int sig);

}  // namespace arbor::mpi::detail
