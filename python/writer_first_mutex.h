#pragma once
/// A reader-writer lock that lets a waiting writer in first. std::shared_mutex (glibc's default
/// rwlock) lets new readers in while a writer waits, so queries from a few Python threads that
/// overlap one another could keep a build() waiting as long as they keep coming. Here, once a
/// writer waits, new readers wait behind it; the readers inside finish, the writer runs, then
/// everyone waiting goes on. Meets the Lockable and SharedLockable requirements (std::unique_lock,
/// std::shared_lock).
#include <condition_variable>
#include <cstddef>
#include <mutex>

namespace arbor::python {

class WriterFirstMutex {
public:
    void lock() {
        std::unique_lock l(m_);
        ++writers_waiting_;
        changed_.wait(l, [&] { return !writing_ && readers_ == 0; });
        --writers_waiting_;
        writing_ = true;
    }
    void unlock() {
        {
            const std::lock_guard l(m_);
            writing_ = false;
        }
        changed_.notify_all();
    }
    void lock_shared() {
        std::unique_lock l(m_);
        changed_.wait(l, [&] { return !writing_ && writers_waiting_ == 0; });
        ++readers_;
    }
    void unlock_shared() {
        bool last = false;
        {
            const std::lock_guard l(m_);
            last = --readers_ == 0;
        }
        if (last) changed_.notify_all();
    }

private:
    std::mutex m_;
    std::condition_variable changed_;
    std::size_t readers_ = 0, writers_waiting_ = 0;
    bool writing_ = false;
};

}  // namespace arbor::python
