#pragma once
/// The connections of `arbor view`: one thread polls the listening socket and every connection
/// (non-blocking sockets, poll(2)). A connection that sends nothing costs a table entry and a
/// socket, never a thread, so idle, half-open or slow clients cannot keep others out.
///
/// - A new connection has `head_timeout_s` from its accept to send a whole request head (at most
///   max_head_bytes; the deadline is not moved by each byte, so a client trickling bytes is cut off
///   too). It is then closed without an answer.
/// - At most `max_connections` are open (lowered to fit the process's open-file limit). At the cap
///   a new connection first drops the oldest one that is lingering after its answer, else the
///   oldest one still reading its request head; WebSockets are never dropped for it (the server
///   caps pages itself). With nothing to drop, the new connection is closed at once.
/// - The handler answers a complete head: plain HTTP (then the connection closes) or a 101 (then
///   it is a WebSocket). WebSocket messages of at most `max_message_bytes` go to the handler (a
///   frame announcing more is refused with 1009 from its header); pings are answered; after
///   `ping_after_s` without input the server pings, after `idle_timeout_s` without input it closes.
/// - Output is queued by send() and close() from any thread: at most `max_output_bytes` unread per
///   connection (beyond, the connection is dropped), and a connection whose output has not moved
///   for `write_timeout_s` is dropped.
/// - Closing: once the last byte (an answer, a close frame) is written the write side is shut and
///   input is read and thrown away for at most `linger_s`, so the peer reads the answer rather than
///   a reset; then the socket is closed.
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "view/http.h"

namespace arbor::view {

using ConnId = std::uint64_t;

struct ConnectionLimits {
    int max_connections = 512;
    double head_timeout_s = 10;
    double ping_after_s = 30;
    double idle_timeout_s = 60;
    double write_timeout_s = 30;
    double linger_s = 2;
    std::size_t max_message_bytes = 4096;
    std::size_t max_output_bytes = std::size_t(64) << 20;
};

/// Why a WebSocket ended.
struct CloseReason {
    int code = 0;            ///< the close code sent or received; 0: the connection just ended
    std::string why;         ///< one line
    bool by_server = false;  ///< the server ended it (a bad frame or message, a timeout, stop())
};

/// What the server does with requests and messages. Called on the loop thread only, never with
/// the loop's lock held, so it may call send() and close().
class ConnectionHandler {
public:
    virtual ~ConnectionHandler() = default;
    struct Answer {
        std::string bytes;     ///< the whole HTTP answer
        bool upgrade = false;  ///< it is a 101: the connection is a WebSocket from here on
    };
    virtual Answer on_request(ConnId id, const HttpRequest& request, const std::string& peer) = 0;
    /// The connection became a WebSocket (its 101 is queued); send() works from now on.
    virtual void on_open(ConnId id) = 0;
    /// A complete text or binary message.
    virtual void on_message(ConnId id, int opcode, std::string payload) = 0;
    /// A WebSocket ended (after on_open only, once); send() to it returns false from now on.
    virtual void on_closed(ConnId id, const CloseReason& reason) = 0;
};

/// Counts for the logs and the tests.
struct ConnectionStats {
    std::size_t open = 0;              ///< connections open now (all states)
    std::uint64_t accepted = 0;        ///< since start
    std::uint64_t head_timeouts = 0;   ///< closed for not sending a request head in time
    std::uint64_t dropped_at_cap = 0;  ///< dropped (or refused) to make room at max_connections
};

class ConnectionLoop {
public:
    ConnectionLoop(const ConnectionLimits& limits, ConnectionHandler& handler);
    ~ConnectionLoop();
    ConnectionLoop(const ConnectionLoop&) = delete;
    ConnectionLoop& operator=(const ConnectionLoop&) = delete;

    /// Binds and listens on a numeric IPv4 or IPv6 address; std::runtime_error "cannot listen on
    /// ADDRESS:PORT (why)" when it cannot. Returns the port (the one picked when `port` is 0).
    int listen(const std::string& address, int port);
    /// The cap in force (max_connections, lowered to fit the open-file limit).
    int max_connections() const { return max_connections_; }
    /// Starts the loop thread (after listen()).
    void start();
    /// Stops the loop thread, then closes every connection: WebSockets get a close frame (1001) and
    /// on_closed. Idempotent.
    void stop();

    /// Queues a WebSocket message (any thread); false when the connection is gone or closing.
    bool send(ConnId id, int opcode, std::string_view payload);
    /// Queues a close frame (any thread); the loop then closes the connection and calls on_closed
    /// with this code and reason. Nothing is sent after it.
    void close(ConnId id, int code, std::string_view why);
    ConnectionStats stats() const;

private:
    struct Conn;
    void run();
    void accept_new(double now);
    bool drop_oldest_idle();
    void on_readable(ConnId id, Conn& c, double now);
    void on_head(ConnId id, Conn& c, double now);
    void on_frames(ConnId id, Conn& c);
    void on_writable(ConnId id, Conn& c, double now);
    void take_close_requests();
    void check_deadlines(double now);
    /// Queues bytes on the loop thread (HTTP answers, pongs, pings).
    void queue(Conn& c, std::string_view bytes, bool last);
    /// A WebSocket starts its closing (close frame queued or received).
    void begin_closing(ConnId id, Conn& c, const CloseReason& reason);
    /// Closes the socket at once and forgets the connection (on_closed first for a WebSocket).
    void drop(ConnId id, const CloseReason& reason);
    void wake();

    const ConnectionLimits limits_;
    ConnectionHandler& handler_;
    int max_connections_ = 0;
    int listen_fd_ = -1, wake_fd_ = -1;
    std::thread thread_;
    std::atomic<bool> stopping_{false};
    double accept_paused_until_ = 0;
    bool cap_logged_ = false;

    /// The table's structure changes on the loop thread only, under mutex_; other threads look
    /// connections up under mutex_ and touch only their output fields (Conn says which).
    mutable std::mutex mutex_;
    std::map<ConnId, std::unique_ptr<Conn>> conns_;  ///< ids grow with accepts: oldest first
    std::vector<ConnId> close_requests_;             ///< close() calls not yet taken by the loop
    ConnId next_id_ = 1;
    ConnectionStats stats_;
};

}  // namespace arbor::view
