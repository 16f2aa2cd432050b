#include "accel/util/timer.h"
#include "view/server.h"

#include "page.h"
#include "view/session.h"

#include <civetweb.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace arbor::view {

namespace {

enum : int { opcode_continuation = 0x0, opcode_text = 0x1, opcode_binary = 0x2, opcode_close = 0x8, opcode_ping = 0x9,
             opcode_pong = 0xA };

/// RFC 6455 close codes.
enum : int { close_protocol = 1002, close_unsupported = 1003, close_policy = 1008, close_too_big = 1009 };

bool is_ipv6(const std::string& a) { return a.find(':') != std::string::npos; }
bool is_wildcard(const std::string& a) { return a == "0.0.0.0" || a == "::"; }
std::string host_port(const std::string& a, int port) {
    return (is_ipv6(a) ? "[" + a + "]" : a) + ":" + std::to_string(port);
}

/// An HTTP error answer written by hand: in the WebSocket connect handler civetweb's own
/// mg_send_http_error writes nothing (the connection is already marked as a WebSocket).
void refuse_handshake(mg_connection* conn, int status, const char* status_text, const std::string& why) {
    const std::string body = why + "\n";
    mg_printf(conn, "HTTP/1.1 %d %s\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: %zu\r\n"
              "Connection: close\r\n\r\n", status, status_text, body.size());
    mg_write(conn, body.data(), body.size());
}

/// While mg_start runs on this thread, civetweb's complaints are collected here (for the one-line
/// error) instead of printed.
thread_local std::string* start_errors = nullptr;

void log_line(const std::string& s) {
    std::fprintf(stderr, "arbor view: %s\n", s.c_str());
    std::fflush(stderr);
}

}  // namespace

/// One page's connection: the Sink of its Session, and the reassembly of fragmented messages.
struct Server::Client final : Sink {
    Client(Server& server, mg_connection* c, int n, const std::string& address)
        : conn(c), id(n), peer(address),
          session(server.scene_, server.lights_, server.cache_, server.options_.limits, server.options_.initial, *this) {}

    bool send_text(std::string_view text) override { return write(opcode_text, text); }
    bool send_binary(std::string_view bytes) override { return write(opcode_binary, bytes); }
    bool write(int opcode, std::string_view bytes) {
        const std::lock_guard lock(mutex);
        if (!open) return false;
        if (mg_websocket_write(conn, opcode, bytes.data(), bytes.size()) <= 0) open = false;
        return open;
    }
    /// Sends a close frame with `code` and logs why (the data handler then returns 0).
    int refuse(int code, const std::string& why) {
        log_line("client " + std::to_string(id) + " (" + peer + "): closed with " + std::to_string(code) + ": " + why);
        std::string payload{char((code >> 8) & 0xFF), char(code & 0xFF)};
        payload += why.substr(0, 120);  // a control frame carries at most 125 bytes
        // The close frame and `open = false` under one lock: a frame of a pass still running on
        // another thread cannot slip in after the close frame (RFC 6455 5.5.1).
        const std::lock_guard lock(mutex);
        if (open) mg_websocket_write(conn, opcode_close, payload.data(), payload.size());
        open = false;
        return 0;
    }

    mg_connection* conn;
    const int id;
    const std::string peer;
    std::mutex mutex;
    bool open = true;
    std::string partial;  ///< a text message arriving in fragments
    bool in_message = false;
    Session session;
};

Server::Server(const engine::Scene& scene, const accel::BuildConfig& build, const ServerOptions& options)
    : scene_(scene), lights_(scene), cache_(scene.mesh.view(), build), options_(options) {}

Server::~Server() { stop(); }

void Server::start() {
    const std::string& a = options_.listen;
    unsigned char buf[16];
    const bool v6 = is_ipv6(a);
    if (inet_pton(v6 ? AF_INET6 : AF_INET, a.c_str(), buf) != 1)
        throw std::runtime_error("--listen: '" + a + "' is not a numeric IPv4 or IPv6 address");
    if (v6 && !mg_check_feature(MG_FEATURES_IPV6)) throw std::runtime_error("--listen: this civetweb has no IPv6");
    mg_init_library(0);
    const std::string ports = host_port(a, options_.port), threads = std::to_string(options_.max_clients + 4);
    const char* config[] = {"listening_ports", ports.c_str(),
                            "num_threads", threads.c_str(),
                            "request_timeout_ms", "10000",
                            "websocket_timeout_ms", "30000",
                            "enable_websocket_ping_pong", "yes",
                            "enable_keep_alive", "no",
                            // A frame leaves in two writes (header, then payload): with Nagle's algorithm
                            // the payload's last partial segment waited for the page's delayed ACK, about
                            // 40 ms a frame.
                            "tcp_nodelay", "1",
                            "access_control_allow_origin", "",
                            "access_control_allow_methods", "",
                            "access_control_allow_headers", "",
                            nullptr};
    mg_callbacks callbacks{};
    callbacks.log_message = &Server::on_log;
    std::string errors;
    start_errors = &errors;
    ctx_ = mg_start(&callbacks, this, config);
    start_errors = nullptr;
    if (!ctx_) {
        mg_exit_library();
        const auto cut = errors.find('\n');
        throw std::runtime_error("cannot listen on " + ports + " (" +
                                 (errors.empty() ? "in use, or not an address of this machine" : errors.substr(0, cut)) + ")");
    }
    mg_server_port info[4];
    const int n = mg_get_server_ports(ctx_, 4, info);
    port_ = n > 0 ? info[0].port : options_.port;
    any_host_ = is_wildcard(a);
    for (const std::string& h : {std::string("127.0.0.1"), std::string("localhost"), std::string("::1"), a})
        hosts_.insert(host_port(h, port_));
    mg_set_request_handler(ctx_, "**", &Server::on_http, this);
    mg_set_websocket_handler(ctx_, "/ws", &Server::on_ws_connect, &Server::on_ws_ready, &Server::on_ws_data,
                             &Server::on_ws_close, this);
}

std::string Server::url() const {
    return "http://" + host_port(is_wildcard(options_.listen) ? "127.0.0.1" : options_.listen, port_) + "/";
}

void Server::stop() {
    if (!ctx_) return;
    mg_stop(ctx_);  // every connection closes: the close handlers stop the sessions
    ctx_ = nullptr;
    mg_exit_library();
}

int Server::on_log(const mg_connection*, const char* message) {
    std::string m(message);
    while (!m.empty() && (m.back() == '\n' || m.back() == '\r')) m.pop_back();
    if (start_errors) *start_errors += (start_errors->empty() ? "" : "\n") + m;
    else log_line("civetweb: " + m);
    return 1;
}

std::string Server::host_problem(const mg_connection* conn) const {
    const char* host = mg_get_header(conn, "Host");
    if (!host) return "no Host header";
    if (any_host_ || hosts_.count(host)) return {};
    return "Host '" + std::string(host).substr(0, 80) + "' is not this server";
}

int Server::on_http(mg_connection* conn, void* self_ptr) {
    const auto& self = *static_cast<Server*>(self_ptr);
    const mg_request_info* ri = mg_get_request_info(conn);
    if (const std::string p = self.host_problem(conn); !p.empty()) {
        mg_send_http_error(conn, 403, "%s", p.c_str());
        return 403;
    }
    const bool head = std::strcmp(ri->request_method, "HEAD") == 0;
    if (!head && std::strcmp(ri->request_method, "GET") != 0) {
        mg_send_http_error(conn, 405, "%s", "only GET");
        return 405;
    }
    if (std::strcmp(ri->local_uri, "/") != 0) {
        mg_send_http_error(conn, 404, "%s", "not found: this server has one page, at /");
        return 404;
    }
    const std::size_t size = std::strlen(view_page_html);
    mg_printf(conn,
              "HTTP/1.1 200 OK\r\nContent-Type: text/html; charset=utf-8\r\nContent-Length: %zu\r\n"
              "Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\n"
              "Referrer-Policy: no-referrer\r\nContent-Security-Policy: default-src 'none'; script-src 'unsafe-inline'; "
              "style-src 'unsafe-inline'; img-src blob: data:; connect-src 'self'; frame-ancestors 'none'; "
              "base-uri 'none'; form-action 'none'\r\nConnection: close\r\n\r\n",
              size);
    if (!head) mg_write(conn, view_page_html, size);
    return 200;
}

int Server::on_ws_connect(const mg_connection* conn, void* self_ptr) {
    auto& self = *static_cast<Server*>(self_ptr);
    auto* c = const_cast<mg_connection*>(conn);  // mg_write takes a non-const connection
    const mg_request_info* ri = mg_get_request_info(conn);
    std::string why = self.host_problem(conn);
    if (why.empty()) {
        const char* origin = mg_get_header(conn, "Origin");
        const char* host = mg_get_header(conn, "Host");
        if (origin && std::string(origin) != "http://" + std::string(host))
            why = "Origin '" + std::string(origin).substr(0, 80) + "' is not this server's page";
    }
    if (!why.empty()) {
        log_line("refused a WebSocket from " + std::string(ri->remote_addr) + ": " + why);
        refuse_handshake(c, 403, "Forbidden", why);
        return 1;
    }
    if (self.clients_.fetch_add(1) >= self.options_.max_clients) {
        self.clients_.fetch_sub(1);
        log_line("refused a WebSocket from " + std::string(ri->remote_addr) + ": " +
                 std::to_string(self.options_.max_clients) + " pages are open already");
        refuse_handshake(c, 503, "Service Unavailable", "too many pages open");
        return 1;
    }
    return 0;
}

void Server::on_ws_ready(mg_connection* conn, void* self_ptr) {
    auto& self = *static_cast<Server*>(self_ptr);
    const mg_request_info* ri = mg_get_request_info(conn);
    auto* client = new Client(self, conn, self.next_id_.fetch_add(1), ri->remote_addr);
    mg_set_user_connection_data(conn, client);
    log_line("client " + std::to_string(client->id) + " (" + client->peer + ") connected");
    client->send_text(client->session.hello(client->id));
    client->session.start();
}

int Server::on_ws_data(mg_connection* conn, int bits, char* data, std::size_t size, void* self_ptr) {
    auto& self = *static_cast<Server*>(self_ptr);
    auto* client = static_cast<Client*>(mg_get_user_connection_data(conn));
    if (!client) return 0;
    const int opcode = bits & 0xF;
    const bool fin = (bits & 0x80) != 0;
    switch (opcode) {
    case opcode_close: return 0;
    case opcode_ping:
    case opcode_pong: return 1;  // civetweb answers pings itself
    case opcode_text:
        if (client->in_message) return client->refuse(close_protocol, "a new message inside a fragmented one");
        client->partial.clear();
        client->in_message = true;
        break;
    case opcode_continuation:
        if (!client->in_message) return client->refuse(close_protocol, "a continuation without a message");
        break;
    case opcode_binary: return client->refuse(close_unsupported, "binary message (the page sends JSON text)");
    default: return client->refuse(close_protocol, "unknown opcode " + std::to_string(opcode));
    }
    if (client->partial.size() + size > max_message_bytes)
        return client->refuse(close_too_big, "message longer than " + std::to_string(max_message_bytes) + " bytes");
    client->partial.append(data, size);
    if (!fin) return 1;
    client->in_message = false;
    std::string error;
    const auto message = parse_client_message(client->partial, self.options_.limits, &error);
    if (!message) return client->refuse(close_policy, "bad message: " + error);
    client->session.handle(*message);
    return 1;
}

void Server::on_ws_close(const mg_connection* conn, void* self_ptr) {
    auto& self = *static_cast<Server*>(self_ptr);
    auto* client = static_cast<Client*>(mg_get_user_connection_data(conn));
    if (!client) return;
    const accel::Timer stopping;
    client->session.stop();  // cancels the pass in progress, joins the worker
    {
        const std::lock_guard lock(client->mutex);
        client->open = false;
    }
    const SessionCounters n = client->session.counters();
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "client %d (%s) disconnected: %llu frames sent, %llu passes rendered, %llu cancelled "
                  "(the last had run %.1f ms); its work stopped in %.1f ms",
                  client->id, client->peer.c_str(), (unsigned long long)n.frames, (unsigned long long)n.passes,
                  (unsigned long long)n.cancelled, n.cancelled_pass_ms, stopping.ms());
    log_line(buf);
    delete client;
    self.clients_.fetch_sub(1);
}

}  // namespace arbor::view
