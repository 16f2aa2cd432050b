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
struct ResultHead {
    std::uint32_t farm;
    std::uint32_t pad;
    std::uint64_t item;
};

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

bool FarmImpl::needs_more() const {
    return spec_.take && !exhausted_ && !asked_ &&
           (int(queue_.size()) < spec_.low_water || (queue_.empty() && in_hand_ == 0));
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
            const std::uint64_t n = grant(spec_.batch, first);
            for (std::uint64_t i = 0; i < n; ++i) queue_.push_back(first + i);
            exhausted_ = n == 0;
        }
    } else {
        if (needs_more()) job_.kick();
        cv_.wait(lock, [this] { return !queue_.empty() || exhausted_; });
    }
    if (queue_.empty()) return false;
    item = queue_.front();
    queue_.pop_front();
    ++in_hand_;
    if (!root() && needs_more()) job_.kick();
    return true;
}

void FarmImpl::done(std::uint64_t item, std::string result) {
    {
        std::lock_guard lock(mu_);
        --in_hand_;
        if (root()) {
            ++delivered_;
        } else {
            outbox_.emplace_back(item, std::move(result));
        }
    }
    if (root()) {
        cv_.notify_all();
    } else {
        job_.kick();
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
    {
        std::lock_guard lock(mu_);
        if (needs_more()) asked_ = ask = true;
        out.swap(outbox_);
        in_flight_ += int(out.size());
    }
    if (ask) job_.send(0, tag_request, pack(Request{id_, spec_.batch}));
    for (auto& [item, bytes] : out) {
        // The callback runs on the service thread, which also detaches the farm: it finds the
        // farm through the job, so a farm destroyed early (an exception) is never touched.
        job_.send(0, tag_result, pack(ResultHead{id_, 0, item}) + bytes, [job = &job_, id = id_] {
            FarmImpl* farm = job->farm_;
            if (!farm || farm->id_ != id) return;
            {
                std::lock_guard lock(farm->mu_);
                --farm->in_flight_;
            }
            farm->cv_.notify_all();
        });
    }
    return ask || !out.empty();
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
            if (farm->on_result_)
                farm->on_result_(h.item, std::string_view(bytes).substr(sizeof h));
            {
                std::lock_guard lock(farm->mu_);
                ++farm->delivered_;
            }
            farm->cv_.notify_all();
            break;
        }
        default:
            break;  // not ours: dropped
    }
}

}  // namespace arbor::mpi::detail
