#pragma once
/// The web server of `arbor view`: one page, one WebSocket, nothing else. Connections are served by
/// one poll loop (connections.h), pages by their sessions (pages.h); this file holds the policy.
///
/// Safe by default:
/// - It listens on 127.0.0.1 unless told another address.
/// - It serves exactly two things: GET / (the page, embedded in the binary) and the WebSocket at
///   /ws. Every other path is 404, every other method 405; no file is ever read for a request (no
///   document root), the scene comes from the command line.
/// - A request whose Host is not this server's address (DNS rebinding) is refused (403); a
///   WebSocket whose Origin is not this server's page is refused (403) before the handshake. A
///   request without Origin (not a browser) is let through: the browser rule is what stops other
///   pages from driving the viewer.
/// - A bad or oversized message (protocol.h) closes that connection with a close frame (1008,
///   1009, 1003 or 1002) and a line on stderr; the other pages go on. At most max_clients pages
///   at once (503 beyond).
/// - Idle, half-open and slow connections cost a socket, not a thread, and time out; open
///   connections are capped (connections.h has the figures).
/// - stop() closes every connection; each page's render is cancelled and its thread joined.
#include <atomic>
#include <set>
#include <string>

#include "engine/lights.h"
#include "engine/scene.h"
#include "view/connections.h"
#include "view/pages.h"
#include "view/protocol.h"
#include "view/structures.h"

namespace arbor::view {

struct ServerOptions {
    std::string listen = "127.0.0.1";  ///< numeric IPv4 or IPv6 address; 0.0.0.0 or :: for all
    int port = 8080;                   ///< 0: any free port (port() tells which)
    int max_clients = 8;               ///< pages at once
    ConnectionLimits connections;      ///< connections at once, timeouts, buffers
    Limits limits;
    ViewSettings initial;  ///< what a new page starts with
};

class Server final : ConnectionHandler {
public:
    /// `scene` outlives the server.
    Server(const engine::Scene& scene, const accel::BuildConfig& build, const ServerOptions& options);
    ~Server() override;
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    /// Listens; std::runtime_error naming the address when it cannot (in use, not this machine's).
    void start();
    int port() const { return port_; }
    /// http://ADDRESS:PORT/ (127.0.0.1 when listening on every address).
    std::string url() const;
    /// The connection cap in force (ServerOptions, lowered to fit the open-file limit).
    int max_connections() const { return loop_.max_connections(); }
    /// Closes every connection and stops listening (idempotent); logs the connection counts.
    void stop();

private:
    Answer on_request(ConnId id, const HttpRequest& request, const std::string& peer) override;
    void on_open(ConnId id) override;
    void on_message(ConnId id, int opcode, std::string payload) override;
    void on_closed(ConnId id, const CloseReason& reason) override;
    Answer websocket(ConnId id, const HttpRequest& request, const std::string& peer);
    /// Empty when the request's Host is this server, else why not.
    std::string host_problem(const HttpRequest& request) const;

    const engine::Scene& scene_;
    const engine::LightSet lights_;
    StructureCache cache_;
    const ServerOptions options_;
    ConnectionLoop loop_;
    Pages pages_;
    int port_ = 0;
    std::set<std::string> hosts_;  ///< Host values accepted ("127.0.0.1:8080", ...)
    bool any_host_ = false;        ///< listening on every address: any Host
    bool started_ = false;
    std::atomic<bool> stopping_{false};
};

}  // namespace arbor::view
