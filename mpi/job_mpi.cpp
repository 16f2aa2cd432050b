#include "mpi/job_mpi.h"

#include "mpi/farm_mpi.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <unistd.h>

namespace arbor::mpi::detail {

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Blocks the calling application thread for good: the job is being stopped and this process
/// ends by MPI_Abort or mpirun's SIGTERM (both handled on the service thread).
[[noreturn]] void wait_for_the_end() {
    while (true) ::pause();
}

/// How long a rank that reported its failure to rank 0 waits for rank 0 to stop the job before
/// it stops the job itself.
constexpr double fatal_patience_seconds = 10.0;

}  // namespace

MpiJob::MpiJob() {
    std::promise<void> started;
    std::future<void> ready = started.get_future();
    service_ = std::thread([this, &started] { loop(started); });
    try {
        ready.get();
    } catch (...) {
        service_.join();
        throw;
    }
}

MpiJob::~MpiJob() {
    if (!service_.joinable()) return;
    // Everyone meets here before MPI_Finalize, inside the service loop (a late failure of
    // another rank is still received and reported while this rank waits).
    call([this](std::function<void()> done) {
        MPI_Request r;
        MPI_Ibarrier(comm_, &r);
        watch(r, [this, done = std::move(done)] {
            finished_ = true;  // every rank is here: none will fall silent mid-job any more
            done();
        });
    });
    {
        std::lock_guard lock(mu_);
        stopping_ = true;
    }
    wake_.notify_one();
    service_.join();
}

void MpiJob::loop(std::promise<void>& started) {
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        started.set_exception(std::make_exception_ptr(std::runtime_error("MPI_Init_thread failed")));
        return;
    }
    if (provided < MPI_THREAD_FUNNELED) {
        MPI_Finalize();
        started.set_exception(std::make_exception_ptr(
            std::runtime_error("the MPI library does not allow threads beside MPI's own (MPI_THREAD_FUNNELED)")));
        return;
    }
    MPI_Comm_dup(MPI_COMM_WORLD, &comm_);
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    // Host names and process ids of every rank, for messages.
    char name[MPI_MAX_PROCESSOR_NAME] = {};
    int len = 0;
    MPI_Get_processor_name(name, &len);
    std::vector<char> names(std::size_t(size_) * MPI_MAX_PROCESSOR_NAME);
    MPI_Allgather(name, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, names.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, comm_);
    for (int r = 0; r < size_; ++r) hosts_.emplace_back(names.data() + std::size_t(r) * MPI_MAX_PROCESSOR_NAME);
    long pid = long(::getpid());
    pids_.resize(std::size_t(size_));
    MPI_Allgather(&pid, 1, MPI_LONG, pids_.data(), 1, MPI_LONG, comm_);
    MPI_Comm node;
    MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &node_rank_);
    MPI_Comm_free(&node);
    int first_on_node = node_rank_ == 0;
    MPI_Allreduce(&first_on_node, &nodes_, 1, MPI_INT, MPI_SUM, comm_);
    install_signal_handlers();
    heartbeat_ = Heartbeat::from_environment();
    last_turn_ = now_seconds();
    heard_.assign(std::size_t(size_), last_turn_);
    sent_.assign(std::size_t(size_), last_turn_);
    stopping_from_.assign(std::size_t(size_), 0);
    started.set_value();  // `started` lives in the constructor's frame: not touched after this

    // Sleep between idle turns: 50 us after a message (more may follow), doubling up to 5 ms; a
    // post() or kick() from an application thread wakes the thread at once. A wakeup costs about
    // 20 us of CPU on the shared VM (condition variable, MPI_Iprobe): with 2 ms this thread took 2%
    // of a core during a render, with 5 ms (farms keep 25 ms of work queued) ~1%.
    constexpr auto shortest = std::chrono::microseconds(50), longest = std::chrono::microseconds(5000);
    auto pause = shortest;
    while (true) {
        const int busy = step();
        if (busy == 2) pause = shortest;
        std::unique_lock lock(mu_);
        if (stopping_ && posted_.empty() && watched_.empty()) break;
        if (busy == 1 || !posted_.empty() || kicked_) {
            kicked_ = false;
            continue;
        }
        wake_.wait_for(lock, pause, [this] { return kicked_ || !posted_.empty(); });
        kicked_ = false;
        pause = std::min(pause * 2, longest);
    }
    MPI_Comm_free(&comm_);
    MPI_Finalize();
}

int MpiJob::step() {
    bool busy = false;
    const double now = now_seconds();
    check_signals(now);
    std::deque<std::function<void()>> work;
    {
        std::lock_guard lock(mu_);
        work.swap(posted_);
    }
    for (auto& f : work) f(), busy = true;
    bool urgent = false;
    for (std::size_t i = 0; i < watched_.size();) {
        int flag = 0;
        MPI_Test(&watched_[i].request, &flag, MPI_STATUS_IGNORE);
        if (!flag) {
            urgent |= watched_[i].urgent;
            ++i;
            continue;
        }
        std::function<void()> then = std::move(watched_[i].then);
        watched_.erase(watched_.begin() + std::ptrdiff_t(i));
        if (then) then();
        busy = true;
    }
    const bool received = poll_messages();
    if (farm_) busy |= farm_->service_step();
    if (fatal_deadline_ > 0.0 && now > fatal_deadline_) {
        // Rank 0 did not stop the job after this rank's report: stop it from here.
        end_job(fatal_code_, "arbor: rank " + std::to_string(rank_) + ": " + fatal_what_ + " (rank 0 did not answer)");
    }
    keep_alive(now);
    // While the launcher stops the job, answers are awaited: keep polling fast.
    return received || urgent || launcher_stop_since_ > 0.0 ? 2 : busy ? 1 : 0;
}

bool MpiJob::poll_messages() {
    bool any = false;
    while (true) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_, &flag, &st);
        if (!flag) return any;
        any = true;
        heard_[std::size_t(st.MPI_SOURCE)] = now_seconds();  // any message is a sign of life
        if (st.MPI_TAG == tag_fatal) {
            on_fatal(st);
        } else if (st.MPI_TAG == tag_heartbeat || st.MPI_TAG == tag_stopping) {
            char none = 0;
            MPI_Recv(&none, 0, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, comm_, MPI_STATUS_IGNORE);
            if (st.MPI_TAG == tag_stopping) stopping_from_[std::size_t(st.MPI_SOURCE)] = 1;
        } else {
            FarmImpl::on_message(*this, st);
        }
    }
}

void MpiJob::post(std::function<void()> f) {
    {
        std::lock_guard lock(mu_);
        posted_.push_back(std::move(f));
    }
    wake_.notify_one();
}

void MpiJob::kick() {
    {
        std::lock_guard lock(mu_);
        kicked_ = true;
    }
    wake_.notify_one();
}

void MpiJob::watch(MPI_Request request, std::function<void()> then, bool urgent) {
    watched_.push_back({request, std::move(then), urgent});
}

void MpiJob::send(int dest, int tag, std::string bytes, std::function<void()> then) {
    sent_[std::size_t(dest)] = now_seconds();  // counts as a heartbeat
    sending_.push_back(std::move(bytes));
    const auto it = std::prev(sending_.end());
    MPI_Request r;
    MPI_Isend(it->data(), int(it->size()), MPI_BYTE, dest, tag, comm_, &r);
    watch(
        r,
        [this, it, then = std::move(then)] {
            sending_.erase(it);
            if (then) then();
        },
        false);
}

void MpiJob::call(const std::function<void(std::function<void()> done)>& start) {
    std::promise<void> finished;
    std::future<void> f = finished.get_future();
    post([&] { start([&finished] { finished.set_value(); }); });
    f.wait();
}

void MpiJob::require_same(const std::string& what, std::uint64_t value, const std::string& advice) {
    std::vector<std::uint64_t> all(static_cast<std::size_t>(size_));
    call([&](std::function<void()> done) {
        MPI_Request r;
        MPI_Iallgather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, comm_, &r);
        watch(r, std::move(done));
    });
    for (int r = 1; r < size_; ++r) {
        if (all[std::size_t(r)] == all[0]) continue;
        if (rank_ == 0) {
            char line[512];
            std::snprintf(line, sizeof line, "arbor: %s: %s (hash %016llx, rank 0: %016llx): %s",
                          describe_rank(r).c_str(), what.c_str(), (unsigned long long)all[std::size_t(r)],
                          (unsigned long long)all[0], advice.c_str());
            post([this, text = std::string(line)] { end_job(1, text); });
        }
        wait_for_the_end();
    }
}

std::string MpiJob::broadcast(const std::string& bytes) {
    std::string out = bytes;
    std::uint64_t n = bytes.size();
    call([&](std::function<void()> done) {
        MPI_Request r;
        MPI_Ibcast(&n, 1, MPI_UINT64_T, 0, comm_, &r);
        watch(r, [this, &out, &n, done = std::move(done)] {
            out.resize(std::size_t(n));
            MPI_Request r2;
            MPI_Ibcast(out.data(), int(n), MPI_BYTE, 0, comm_, &r2);
            watch(r2, done);
        });
    });
    return out;
}

std::vector<double> MpiJob::sum(const std::vector<double>& values) {
    std::vector<double> out(values.size());
    call([&](std::function<void()> done) {
        MPI_Request r;
        MPI_Iallreduce(values.data(), out.data(), int(values.size()), MPI_DOUBLE, MPI_SUM, comm_, &r);
        watch(r, std::move(done));
    });
    return out;
}

std::unique_ptr<Farm> MpiJob::farm(const FarmSpec& spec, FarmResult on_result) {
    return std::make_unique<FarmImpl>(*this, spec, std::move(on_result));
}

void MpiJob::fail(int code, const std::string& what) {
    if (service_thread()) {
        stop_job(code, what);
    } else {
        post([this, code, what] { stop_job(code, what); });
    }
    wait_for_the_end();
}

void MpiJob::set_cleanup(std::function<void()> cleanup) {
    call([&](std::function<void()> done) {
        cleanup_ = std::move(cleanup);
        done();
    });
}

void MpiJob::end_job(int code, const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
    if (cleanup_) cleanup_();
    MPI_Abort(comm_, code);
    ::_exit(code);  // not reached: MPI_Abort ends this process
}

void MpiJob::quit_quietly() {
    if (cleanup_) cleanup_();
    ::_exit(1);
}

void MpiJob::stop_job(int code, const std::string& what) {
    if (rank_ == 0) end_job(code, size_ > 1 ? "arbor: rank 0: " + what : "arbor: " + what);
    if (fatal_sent_.exchange(true)) return;
    std::string msg(sizeof(std::int32_t), '\0');
    const std::int32_t c = code;
    std::memcpy(msg.data(), &c, sizeof c);
    msg += what;
    send(0, tag_fatal, std::move(msg));
    fatal_code_ = code;
    fatal_what_ = what;
    fatal_deadline_ = now_seconds() + fatal_patience_seconds;
}

void MpiJob::on_fatal(const MPI_Status& st) {
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::string msg(std::size_t(n), '\0');
    MPI_Recv(msg.data(), n, MPI_BYTE, st.MPI_SOURCE, tag_fatal, comm_, MPI_STATUS_IGNORE);
    if (rank_ != 0 || msg.size() < sizeof(std::int32_t)) return;
    std::int32_t code = 1;
    std::memcpy(&code, msg.data(), sizeof code);
    end_job(code, "arbor: rank " + std::to_string(st.MPI_SOURCE) + ": " + (msg.c_str() + sizeof code));
}

std::string MpiJob::describe_rank(int r) const {
    return "rank " + std::to_string(r) + " (pid " + std::to_string(pids_[std::size_t(r)]) + " on " +
           hosts_[std::size_t(r)] + ")";
}

void MpiJob::check_signals(double now) {
    if (const int sig = caught_crash_signal(); sig && !crash_reported_) {
        crash_reported_ = true;
        stop_job(4, "crashed: " + signal_text(sig));
    }
    // mpirun stopping the job: a rank failed (and said so), or mpirun itself was interrupted.
    if (stopped_by_launcher()) on_launcher_stop(now);
    if (guardian_lost() && !guardian_reported_) {
        // mpirun sees the process it started die by a signal and stops the job (exit 128 +
        // signal, its own rule); the line says which rank and why.
        guardian_reported_ = true;
        stop_job(4, "its guardian (pid " + std::to_string(guardian_process()) + " on " + hosts_[std::size_t(rank_)] +
                        ", the process mpirun started) was killed (SIGKILL: kill -9, or the out-of-memory killer); "
                        "the job stops");
    }
    if (const int sig = caught_stop_signal(); sig && !stop_reported_) {
        stop_reported_ = true;
        const long sender = stop_signal_sender();
        stop_job(4, "stopped by " + signal_text(sig) + (sender > 0 ? " (sent by pid " + std::to_string(sender) + ")" : ""));
    }
}

}  // namespace arbor::mpi::detail

extern "C" arbor::mpi::Job* arbor_mpi_open(int abi, std::string* error) {
    if (abi != arbor::mpi::job_abi_version) {
        if (error)
            *error = "the module arbor_mpi.so speaks version " + std::to_string(arbor::mpi::job_abi_version) +
                     " of mpi/job.h, arbor version " + std::to_string(abi) + ": rebuild both";
        return nullptr;
    }
    try {
        return new arbor::mpi::detail::MpiJob();
    } catch (const std::exception& e) {
        if (error) *error = e.what();
        return nullptr;
    }
}
