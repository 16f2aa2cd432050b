#pragma once
/// The MPI job this process belongs to, as arbor uses it: a few collectives, a farm that hands
/// out numbered work items on request, and a way to stop the whole job with one line. No MPI
/// header here: the implementation is the module `arbor_mpi.so` (mpi/job_mpi.cpp), which `arbor`
/// loads with dlopen only when a launcher started it (mpi/launcher.h), so that a plain call
/// neither loads nor initialises MPI. Inside the module, one thread of its own makes every MPI
/// call (MPI_THREAD_FUNNELED); the calls below may come from any thread of the application.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace arbor::mpi {

/// Bumped whenever this interface changes: `arbor` refuses a module built from another version.
inline constexpr int job_abi_version = 2;

/// How a farm hands out items [0, items): a taking rank asks rank 0 for up to `batch` items when
/// fewer than `low_water` are queued for it (0: only when it has nothing queued or in hand).
/// Rank 0 answers with a run of consecutive items, smaller towards the end (guided: about
/// remaining / (2 x takers), at least 1, at most `batch`), so slow ranks take fewer items.
struct FarmSpec {
    std::uint64_t items = 0;
    int batch = 1;
    int low_water = 0;
    bool take = true;  ///< false: this rank takes no items (rank 0 still hands them out)
};

/// One distribution of items over the ranks; created by every rank in the same order.
class Farm {
public:
    virtual ~Farm() = default;
    /// The next item for this rank: blocks until one is granted; false once none is left.
    /// Thread-safe.
    virtual bool next(std::uint64_t& item) = 0;
    /// `item` is finished. On other ranks `result` goes to rank 0; on rank 0 only counts (the
    /// caller keeps its own results). Thread-safe.
    virtual void done(std::uint64_t item, std::string result) = 0;
    /// Waits until rank 0 holds every item's result (on rank 0) or every result of this rank has
    /// been sent (elsewhere).
    virtual void finish() = 0;
};

/// Rank 0 receives another rank's result (on the module's thread, concurrently with the
/// application's threads).
using FarmResult = std::function<void(std::uint64_t item, std::string_view result)>;

class Job {
public:
    /// Every rank waits for the others, then MPI is finalised.
    virtual ~Job() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// This rank's host name, and its rank among the ranks on that host (MPI_COMM_TYPE_SHARED).
    virtual std::string host() const = 0;
    virtual int node_rank() const = 0;
    virtual int nodes() const = 0;

    /// Every rank passes its `value` (e.g. a hash of the scene); returns when all equal rank 0's.
    /// Otherwise rank 0 prints "arbor: rank R (...): <complaint> (hashes): <advice>" naming the
    /// first such rank, and the job stops with exit status 1. Collective.
    virtual void require_same(const std::string& complaint, std::uint64_t value, const std::string& advice) = 0;
    /// Rank 0's `bytes` on every rank. Collective.
    virtual std::string broadcast(const std::string& bytes) = 0;
    /// Element-wise sums over the ranks, on every rank. Collective.
    virtual std::vector<double> sum(const std::vector<double>& values) = 0;
    /// Starts the next farm (collective in order: every rank calls it for every farm).
    /// `on_result` is called on rank 0 only.
    virtual std::unique_ptr<Farm> farm(const FarmSpec& spec, FarmResult on_result) = 0;

    /// Stops the whole job: rank 0 prints one line "arbor: rank R: <what>" (R: this rank), and
    /// mpirun exits with `code` (MPI_Abort). Never returns.
    [[noreturn]] virtual void fail(int code, const std::string& what) = 0;
    /// `cleanup` runs on the module's thread just before this process ends with the job without
    /// unwinding (MPI_Abort, a stop by the launcher): it removes what must not outlive the job,
    /// e.g. unfinished output files. It must not wait for application threads (one may hold a
    /// crash signal).
    virtual void set_cleanup(std::function<void()> cleanup) = 0;
};

}  // namespace arbor::mpi

/// The module's entry point (extern "C" for dlsym): initialises MPI on the module's thread and
/// returns the job, or nullptr with `*error` set. `abi` must equal job_abi_version.
extern "C" arbor::mpi::Job* arbor_mpi_open(int abi, std::string* error);
