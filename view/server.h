#pragma once
/// The web server of `arbor view` (civetweb): one page, one WebSocket, nothing else.
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
/// - stop() closes every connection; each page's render is cancelled and its thread joined.
#include "engine/lights.h"
#include "engine/scene.h"
#include "view/protocol.h"
#include "view/structures.h"

#include <atomic>
#include <set>
#include <string>

struct mg_context;
struct mg_connection;

namespace arbor::view {

struct ServerOptions {
    std::string listen = "127.0.0.1";  ///< numeric IPv4 or IPv6 address; 0.0.0.0 or :: for all
    int port = 8080;                   ///< 0: any free port (port() tells which)
    int max_clients = 8;
    Limits limits;
    ViewSettings initial;  ///< what a new page starts with
};

class Server {
public:
    /// `scene` outlives the server.
    Server(const engine::Scene& scene, const accel::BuildConfig& build, const ServerOptions& options);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    /// Listens; std::runtime_error naming the address when it cannot (in use, not this machine's).
    void start();
    int port() const { return port_; }
    /// http://ADDRESS:PORT/ (127.0.0.1 when listening on every address).
    std::string url() const;
    /// Closes every connection and stops listening (idempotent).
    void stop();

    struct Client;

private:
    static int on_http(mg_connection* conn, void* self);
    static int on_ws_connect(const mg_connection* conn, void* self);
    static void on_ws_ready(mg_connection* conn, void* self);
    static int on_ws_data(mg_connection* conn, int bits, char* data, std::size_t size, void* self);
    static void on_ws_close(const mg_connection* conn, void* self);
    static int on_log(const mg_connection* conn, const char* message);
    /// Empty when the request's Host is this server, else why not.
    std::string host_problem(const mg_connection* conn) const;

    const engine::Scene& scene_;
    const engine::LightSet lights_;
    StructureCache cache_;
    const ServerOptions options_;
    mg_context* ctx_ = nullptr;
    int port_ = 0;
    std::set<std::string> hosts_;  ///< Host values accepted ("127.0.0.1:8080", ...)
    bool any_host_ = false;        ///< listening on every address: any Host
    std::atomic<int> clients_{0}, next_id_{1};
};

}  // namespace arbor::view
