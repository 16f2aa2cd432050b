#include "view/pages.h"

#include <cstdio>

#include "accel/util/timer.h"
#include "view/log.h"
#include "view/session.h"
#include "view/websocket.h"

namespace arbor::view {

/// One page: the Sink of its Session, writing through the connection loop.
struct Pages::Page final : Sink {
    Page(Pages& pages, ConnId c, int n, const std::string& address)
        : loop(pages.loop_),
          conn(c),
          number(n),
          peer(address),
          session(pages.scene_, pages.lights_, pages.cache_, pages.limits_, pages.initial_, *this) {}

    bool send_text(std::string_view text) override { return loop.send(conn, ws::text, text); }
    bool send_binary(std::string_view bytes) override { return loop.send(conn, ws::binary, bytes); }
    std::string name() const { return "client " + std::to_string(number) + " (" + peer + ")"; }

    ConnectionLoop& loop;
    const ConnId conn;
    const int number;
    const std::string peer;
    Session session;
};

Pages::Pages(const engine::Scene& scene, const engine::LightSet& lights, StructureCache& cache, const Limits& limits,
             const ViewSettings& initial, int max_pages, ConnectionLoop& loop)
    : scene_(scene),
      lights_(lights),
      cache_(cache),
      limits_(limits),
      initial_(initial),
      max_pages_(max_pages),
      loop_(loop),
      stopper_([this] { stopper(); }) {}

Pages::~Pages() { stop(); }

bool Pages::reserve() {
    const std::lock_guard lock(mutex_);
    if (held_ >= max_pages_) return false;
    ++held_;
    return true;
}

void Pages::add(ConnId conn, const std::string& peer) {
    const std::lock_guard lock(mutex_);
    open_.emplace(conn, std::make_unique<Page>(*this, conn, next_number_++, peer));
}

void Pages::open(ConnId conn) {
    Page* page = nullptr;
    {
        const std::lock_guard lock(mutex_);
        const auto it = open_.find(conn);
        if (it == open_.end()) return;
        page = it->second.get();
    }
    // Outside the lock: only the loop thread calls open, handle and closed, so the page stays.
    log_line(page->name() + " connected");
    page->send_text(page->session.hello(page->number));
    page->session.start();
}

void Pages::handle(ConnId conn, const ClientMessage& m) {
    Page* page = nullptr;
    {
        const std::lock_guard lock(mutex_);
        const auto it = open_.find(conn);
        if (it == open_.end()) return;
        page = it->second.get();
    }
    page->session.handle(m);
}

std::string Pages::name(ConnId conn) const {
    const std::lock_guard lock(mutex_);
    const auto it = open_.find(conn);
    return it == open_.end() ? "connection " + std::to_string(conn) : it->second->name();
}

void Pages::closed(ConnId conn) {
    {
        const std::lock_guard lock(mutex_);
        const auto it = open_.find(conn);
        if (it == open_.end()) return;
        ending_.push_back(std::move(it->second));
        open_.erase(it);
    }
    wake_.notify_all();
}

int Pages::held() const {
    const std::lock_guard lock(mutex_);
    return held_;
}

void Pages::stop() {
    {
        const std::lock_guard lock(mutex_);
        for (auto& [conn, page] : open_) ending_.push_back(std::move(page));
        open_.clear();
        quit_ = true;
    }
    wake_.notify_all();
    if (stopper_.joinable()) stopper_.join();
}

void Pages::stopper() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return quit_ || !ending_.empty(); });
        if (ending_.empty()) return;  // quit_, and every page stopped
        std::unique_ptr<Page> page = std::move(ending_.front());
        ending_.pop_front();
        lock.unlock();
        const accel::Timer stopping;
        page->session.stop();  // cancels the pass in progress, joins the worker
        const SessionCounters n = page->session.counters();
        char buf[256];
        std::snprintf(
            buf, sizeof buf,
            " disconnected: %llu frames sent, %llu passes rendered, %llu cancelled (the last had run %.1f ms); "
            "its work stopped in %.1f ms",
            (unsigned long long)n.frames, (unsigned long long)n.passes, (unsigned long long)n.cancelled,
            n.cancelled_pass_ms, stopping.ms());
        log_line(page->name() + buf);
        page.reset();
        lock.lock();
        --held_;
    }
}

}  // namespace arbor::view
