#include "mpi/farm_mpi.h"

#include <algorithm>
#include <cstring>

namespace arbor::mpi::detail {

namespace {

struct Request {
    std::uint32_t farm;
    std::int32_t want;
};
struct Grant {
    std::uint32_t farm;
    std::uint32_t pad;
    std::uint64_t first, count;
};
/// A RESULT message: this head, then `count` records of {item, length} each followed by `length`
/// bytes.
struct ResultHead {
    std::uint32_t farm;
    std::uint32_t count;
};
struct ResultRecord {
    std::uint64_t item, length;
};

/// Results are sent together: a message when this many bytes wait, when the oldest has waited
/// this long, or when the rank has nothing left queued (the end of its share). Rank 0 pays per
/// message more than per byte (measured: ~60 us of CPU per one-tile message on the shared VM).
constexpr std::size_t result_bytes = std::size_t(64) << 10;
constexpr double result_seconds = 0.02;

template <class T>
std::string pack(const T& v) {
    return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string receive(MpiJob& job, const MPI_Status& st) {
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::string bytes(std::size_t(n), '\0');
    MPI_Recv(bytes.data(), n, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, job.comm(), MPI_STATUS_IGNORE);
    return bytes;
}

template <class T>
T unpack(const std::string& bytes) {
    T v{};
    std::memcpy(&v, bytes.data(), std::min(sizeof v, bytes.size()));
    return v;
}

}  // namespace

FarmImpl::FarmImpl(MpiJob& job, const FarmSpec& spec, FarmResult on_result)
    : job_(job), spec_(spec), on_result_(std::move(on_result)) {
    job_.call([this](std::function<void()> done) {
        id_ = ++job_.farms_started_;
        job_.farm_ = this;
        // Requests that reached rank 0 before it started this farm.
        auto& early = job_.early_requests_;
        for (auto it = early.begin(); it != early.end();) {
            const Request r = unpack<Request>(it->second);
            if (r.farm != id_) {
                ++it;
                continue;
            }
            serve(it->first, r.want);
            it = early.erase(it);
        }
        done();
    });
}

FarmImpl::~FarmImpl() {
    job_.call([this](std::function<void()> done) {
        if (job_.farm_ == this) job_.farm_ = nullptr;
        done();
    });
}

namespace {
/// Work a rank asks for at a time (at its own rate so far; at least its threads' batch); it asks
/// again when half of that is left, 25 ms, five times the service threads' longest sleep.
constexpr double cover_seconds = 0.05;
}  // namespace

int FarmImpl::want() const {
    if (spec_.low_water == 0 || completed_ == 0) return std::max(spec_.batch, 1);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    const double rate = double(completed_) / std::max(elapsed, 1e-6);
    return int(std::clamp(rate * cover_seconds, double(std::max(spec_.batch, 1)), 65536.0));
}

bool FarmImpl::needs_more() const {
    if (!spec_.take || exhausted_ || asked_) return false;
    if (queue_.empty() && in_hand_ == 0) return true;
    return spec_.low_water > 0 && int(queue_.size()) < std::max(spec_.low_water, want() / 2);
}

std::uint64_t FarmImpl::grant(int want, std::uint64_t& first) {
    const std::uint64_t remaining = spec_.items - next_item_;
    if (remaining == 0) return 0;
    // Guided: large runs while much is left, single items at the end, so that the ranks finish
    // together however fast each one is.
    const std::uint64_t share = (remaining + 2 * std::uint64_t(job_.size()) - 1) / (2 * std::uint64_t(job_.size()));
    const std::uint64_t n = std::min({remaining, std::max<std::uint64_t>(share, 1), std::uint64_t(std::max(want, 1))});
    first = next_item_;
    next_item_ += n;
    return n;
}

void FarmImpl::serve(int from, int want) {
    Grant g{id_, 0, 0, 0};
    {
        std::lock_guard lock(mu_);
        g.count = grant(want, g.first);
    }
    job_.send(from, tag_grant, pack(g));
}

bool FarmImpl::next(std::uint64_t& item) {
    std::unique_lock lock(mu_);
    if (!spec_.take) return false;
    if (root()) {
        if (queue_.empty() && !exhausted_) {
            std::uint64_t first = 0;
            const std::uint64_t n = grant(want(), first);
            for (std::uint64_t i = 0; i < n; ++i) queue_.push_back(first + i);
            exhausted_ = n == 0;
        }
    } else {
        if (needs_more()) job_.kick();
        cv_.wait(lock, [this] { return !queue_.empty() || exhausted_; });
    }
    if (queue_.empty()) return false;
    if (completed_ == 0 && in_hand_ == 0) started_ = std::chrono::steady_clock::now();
    item = queue_.front();
    queue_.pop_front();
    ++in_hand_;
    if (!root() && needs_more()) job_.kick();
    return true;
}

void FarmImpl::done(std::uint64_t item, std::string result) {
    bool flush = false;
    {
        std::lock_guard lock(mu_);
        --in_hand_;
        ++completed_;
        if (root()) {
            ++delivered_;
        } else {
            if (outbox_.empty()) oldest_ = std::chrono::steady_clock::now();
            outbox_bytes_ += result.size();
            outbox_.emplace_back(item, std::move(result));
        }
        flush = exhausted_ || queue_.empty() || needs_more();
    }
    if (root()) {
        cv_.notify_all();
    } else if (flush) {
        job_.kick();  // the frame's last results: send now (otherwise at the service thread's next turn)
    }
}

void FarmImpl::finish() {
    std::unique_lock lock(mu_);
    if (root()) {
        cv_.wait(lock, [this] { return delivered_ == spec_.items; });
    } else {
        cv_.wait(lock, [this] {
            return (!spec_.take || exhausted_) && queue_.empty() && in_hand_ == 0 && outbox_.empty() && in_flight_ == 0;
        });
    }
}

bool FarmImpl::service_step() {
    if (root()) return false;
    std::deque<std::pair<std::uint64_t, std::string>> out;
    bool ask = false;
    int n = 0;
    {
        std::lock_guard lock(mu_);
        if (needs_more()) asked_ = ask = true, n = want();
        const double age = std::chrono::duration<double>(std::chrono::steady_clock::now() - oldest_).count();
        if (!outbox_.empty() && (outbox_bytes_ >= result_bytes || age >= result_seconds || queue_.empty())) {
            out.swap(outbox_);
            outbox_bytes_ = 0;
            ++in_flight_;
        }
    }
    if (ask) job_.send(0, tag_request, pack(Request{id_, n}));
    if (out.empty()) return ask;
    std::string msg = pack(ResultHead{id_, std::uint32_t(out.size())});
    for (const auto& [item, bytes] : out) msg += pack(ResultRecord{item, bytes.size()}) + bytes;
    // The callback runs on the service thread, which also detaches the farm: it finds the farm
    // through the job, so a farm destroyed early (an exception) is never touched.
    job_.send(0, tag_result, std::move(msg), [job = &job_, id = id_] {
        FarmImpl* farm = job->farm_;
        if (!farm || farm->id_ != id) return;
        {
            std::lock_guard lock(farm->mu_);
            --farm->in_flight_;
        }
        farm->cv_.notify_all();
    });
    return true;
}

void FarmImpl::on_message(MpiJob& job, const MPI_Status& st) {
    const std::string bytes = receive(job, st);
    FarmImpl* farm = job.farm_;
    switch (st.MPI_TAG) {
        case tag_request: {
            const Request r = unpack<Request>(bytes);
            if (farm && farm->id_ == r.farm) {
                farm->serve(st.MPI_SOURCE, r.want);
            } else if (r.farm > job.farms_started_) {
                job.early_requests_.emplace_back(st.MPI_SOURCE, bytes);  // rank 0 has not started it yet
            } else {
                job.send(st.MPI_SOURCE, tag_grant, pack(Grant{r.farm, 0, 0, 0}));  // that farm is over
            }
            break;
        }
        case tag_grant: {
            const Grant g = unpack<Grant>(bytes);
            if (!farm || farm->id_ != g.farm) break;
            {
                std::lock_guard lock(farm->mu_);
                for (std::uint64_t i = 0; i < g.count; ++i) farm->queue_.push_back(g.first + i);
                farm->exhausted_ = g.count == 0;
                farm->asked_ = false;
            }
            farm->cv_.notify_all();
            break;
        }
        case tag_result: {
            const ResultHead h = unpack<ResultHead>(bytes);
            if (!farm || farm->id_ != h.farm || bytes.size() < sizeof h) break;
            std::size_t at = sizeof h;
            std::uint64_t got = 0;
            for (std::uint32_t k = 0; k < h.count && at + sizeof(ResultRecord) <= bytes.size(); ++k) {
                const ResultRecord r = unpack<ResultRecord>(bytes.substr(at, sizeof(ResultRecord)));
                at += sizeof r;
                if (r.length > bytes.size() - at) break;  // malformed: the rest is dropped
                if (farm->on_result_) farm->on_result_(r.item, std::string_view(bytes).substr(at, r.length));
                at += r.length;
                ++got;
            }
            {
                std::lock_guard lock(farm->mu_);
                farm->delivered_ += got;
            }
            farm->cv_.notify_all();
            break;
        }
        default:
            break;  // not ours: dropped
    }
}

}  // namespace arbor::mpi::detail
