#pragma once
/// The farm of mpi/job.h over MPI messages (inside the module). Rank 0 keeps the next free item
/// and answers requests; every taking rank keeps a queue of granted items for its threads.
///
///   rank r -> 0: REQUEST {farm, want}       when its queue runs low (the service thread sends it)
///   0 -> rank r: GRANT {farm, first, count} count 0: nothing left, the rank's next() ends
///   rank r -> 0: RESULT {farm, n} n x {item, length, bytes}  finished items, several per message
///
/// Rank 0 grants itself items directly under the farm's lock. Messages use the host's byte order
/// (a job's machines are assumed to share it, as they share the binary).
#include "mpi/job_mpi.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>

namespace arbor::mpi::detail {

class FarmImpl final : public Farm {
public:
    FarmImpl(MpiJob& job, const FarmSpec& spec, FarmResult on_result);  ///< attaches to the service thread
    ~FarmImpl() override;                                               ///< detaches

    bool next(std::uint64_t& item) override;
    void done(std::uint64_t item, std::string result) override;
    void finish() override;

    /// Service thread: sends a request when the queue runs low, and the finished results.
    bool service_step();
    /// Service thread: a REQUEST, GRANT or RESULT message (for this farm or another).
    static void on_message(MpiJob& job, const MPI_Status& st);

private:
    bool root() const { return job_.rank() == 0; }
    bool needs_more() const;  ///< under mu_
    /// Under mu_: how many items to ask for. At least spec_.batch, and enough for `cover_seconds`
    /// of work at this rank's rate so far, so that a request's round trip (up to a few ms: the
    /// service threads sleep between turns) never leaves the threads without items when items
    /// are cheap; when low_water is 0 (one item at a time), spec_.batch.
    int want() const;
    /// Rank 0, under mu_: the next run of at most `want` items; returns its length (0: none left).
    std::uint64_t grant(int want, std::uint64_t& first);
    /// Rank 0, service thread: answers a request of rank `from`.
    void serve(int from, int want);

    MpiJob& job_;
    std::uint32_t id_ = 0;  ///< set on the service thread: farms are numbered alike on every rank
    const FarmSpec spec_;
    FarmResult on_result_;

    std::mutex mu_;
    std::condition_variable cv_;
    std::deque<std::uint64_t> queue_;  ///< granted to this rank, not yet taken by next()
    int in_hand_ = 0;                  ///< taken by next(), not yet done()
    bool exhausted_ = false, asked_ = false;
    std::deque<std::pair<std::uint64_t, std::string>> outbox_;  ///< results not yet sent (rank > 0)
    std::size_t outbox_bytes_ = 0;
    std::chrono::steady_clock::time_point oldest_{};            ///< when the oldest of them finished
    int in_flight_ = 0;                                         ///< result messages being sent (rank > 0)
    std::uint64_t next_item_ = 0, delivered_ = 0;               ///< rank 0
    std::uint64_t completed_ = 0;                               ///< done() on this rank
    std::chrono::steady_clock::time_point started_{};           ///< this rank's first next()
};

}  // namespace arbor::mpi::detail
