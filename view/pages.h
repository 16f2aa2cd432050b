#pragma once
/// The pages `arbor view` serves: one Session per WebSocket, at most `max_pages` at once, each
/// stopped on a thread of its own kind (the stopper) when its connection ends, so the connection
/// loop never waits for a render to cancel or a structure build to finish.
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "engine/lights.h"
#include "engine/scene.h"
#include "view/connections.h"
#include "view/protocol.h"
#include "view/structures.h"

namespace arbor::view {

class Pages {
public:
    /// Everything referenced outlives the pages; `loop` carries their messages.
    Pages(const engine::Scene& scene, const engine::LightSet& lights, StructureCache& cache, const Limits& limits,
          const ViewSettings& initial, int max_pages, ConnectionLoop& loop);
    ~Pages();
    Pages(const Pages&) = delete;
    Pages& operator=(const Pages&) = delete;

    /// Holds a place for a new page; false when `max_pages` are held (nothing is held then).
    bool reserve();
    /// The WebSocket `conn` from `peer` takes the place reserve() held: its session, not started.
    void add(ConnId conn, const std::string& peer);
    /// Sends the page its hello and starts its session.
    void open(ConnId conn);
    /// A message from the page, parsed and checked.
    void handle(ConnId conn, const ClientMessage& m);
    /// "client N (ADDRESS)" for log lines; "connection N" when `conn` is no page.
    std::string name(ConnId conn) const;
    /// The page's connection ended: its session is stopped on the stopper thread, which then logs
    /// what it did and frees its place.
    void closed(ConnId conn);
    /// Stops every session and the stopper thread (idempotent).
    void stop();
    /// Places held: pages open, and pages whose sessions are still stopping.
    int held() const;

private:
    struct Page;
    void stopper();

    const engine::Scene& scene_;
    const engine::LightSet& lights_;
    StructureCache& cache_;
    const Limits limits_;
    const ViewSettings initial_;
    const int max_pages_;
    ConnectionLoop& loop_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::map<ConnId, std::unique_ptr<Page>> open_;
    std::deque<std::unique_ptr<Page>> ending_;  ///< closed, session not yet stopped
    int held_ = 0;
    int next_number_ = 1;
    bool quit_ = false;
    std::thread stopper_;
};

}  // namespace arbor::view
