#pragma once
/// One page's render loop (`arbor view`): a worker thread that renders one sample per pixel per
/// pass into an Accumulator while the camera is still, and sends each refined picture as a frame.
///
/// - A new camera or image setting starts the picture over. A refining pass that is running is
///   cancelled at once (its tiles stop being scheduled; TBB cancellation); the first pass of a
///   camera always completes and is shown, so a camera being dragged still gets frames.
/// - One frame is in flight: the next is sent once the page acknowledges the last (its figures
///   are then not held back by a slow page); a refinement of a camera that has moved on is dropped.
/// - stop() (the page closed, or the server stops) cancels the pass in progress, joins the thread,
///   and guarantees the Sink is never called again.
/// - Each session renders in its own tbb::task_arena of the page's thread count; structures come
///   from the shared StructureCache.
#include "engine/lights.h"
#include "engine/scene.h"
#include "view/protocol.h"
#include "view/structures.h"

#include <tbb/task_group.h>

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

namespace arbor::view {

/// Where a session's messages go. Returns false when the page is gone. Called from the session's
/// worker thread only.
class Sink {
public:
    virtual ~Sink() = default;
    virtual bool send_text(std::string_view text) = 0;
    virtual bool send_binary(std::string_view bytes) = 0;
};

/// What a session did, for its closing log line and the tests.
struct SessionCounters {
    std::uint64_t frames = 0;     ///< frames sent
    std::uint64_t passes = 0;     ///< passes rendered to the end
    std::uint64_t cancelled = 0;  ///< passes cancelled (camera moved, settings changed, page closed)
    double cancelled_pass_ms = 0; ///< how long the last cancelled pass had run when it stopped
};

class Session {
public:
    /// `scene`, `lights` and `cache` outlive the session.
    Session(const engine::Scene& scene, const engine::LightSet& lights, StructureCache& cache, const Limits& limits,
            const ViewSettings& initial, Sink& sink);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    /// The "hello" message: scene, camera, choices, limits, settings, and the number `client` the
    /// server's log calls this page by.
    std::string hello(int client) const;
    /// Starts the worker thread (after the hello was sent).
    void start();
    /// A message from the page (already parsed and checked).
    void handle(const ClientMessage& m);
    /// Stops the worker (idempotent); afterwards the Sink is not used again.
    void stop();
    SessionCounters counters() const;

private:
    void run();
    void loop();
    bool wait_for_work(std::uint64_t acc_version, int samples, ViewSettings& s, engine::Camera& cam, std::uint64_t& version);
    /// Cancels the running pass unless it is the first of its picture (lock held).
    void cancel_refinement_locked();

    const engine::Scene& scene_;
    const engine::LightSet& lights_;
    StructureCache& cache_;
    const Limits limits_;
    Sink& sink_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    ViewSettings settings_;
    engine::Camera camera_;
    std::uint64_t version_ = 0;       ///< bumped by every change that starts the picture over
    std::uint64_t sent_frame_ = 0;    ///< number of the last frame sent
    bool acked_ = true;               ///< the page has shown frame sent_frame_
    bool stop_ = false;
    tbb::task_group* running_ = nullptr;  ///< the pass in progress (mutex_)
    bool running_first_ = false;          ///< it is the first pass of its picture
    SessionCounters counters_;
    std::thread worker_;
};

}  // namespace arbor::view
