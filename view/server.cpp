#include "view/server.h"

#include <cstring>

#include "page.h"
#include "view/log.h"
#include "view/websocket.h"

namespace arbor::view {

namespace {

bool is_ipv6(const std::string& a) { return a.find(':') != std::string::npos; }
bool is_wildcard(const std::string& a) { return a == "0.0.0.0" || a == "::"; }
std::string host_port(const std::string& a, int port) {
    return (is_ipv6(a) ? "[" + a + "]" : a) + ":" + std::to_string(port);
}

std::string page_answer(bool head) {
    const std::size_t size = std::strlen(view_page_html);
    std::string out =
        "HTTP/1.1 200 OK\r\nContent-Type: text/html; charset=utf-8\r\nContent-Length: " + std::to_string(size) +
        "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\n"
        "Referrer-Policy: no-referrer\r\nContent-Security-Policy: default-src 'none'; script-src 'unsafe-inline'; "
        "style-src 'unsafe-inline'; img-src blob: data:; connect-src 'self'; frame-ancestors 'none'; "
        "base-uri 'none'; form-action 'none'\r\nConnection: close\r\n\r\n";
    if (!head) out.append(view_page_html, size);
    return out;
}

}  // namespace

Server::Server(const engine::Scene& scene, const accel::BuildConfig& build, const ServerOptions& options)
    : scene_(scene),
      lights_(scene),
      cache_(scene.mesh, scene.placed, build),
      options_(options),
      loop_(options.connections, *this),
      pages_(scene_, lights_, cache_, options_.limits, options_.initial, options_.max_clients, loop_) {}

Server::~Server() { stop(); }

void Server::start() {
    port_ = loop_.listen(options_.listen, options_.port);
    any_host_ = is_wildcard(options_.listen);
    for (const std::string& h :
         {std::string("127.0.0.1"), std::string("localhost"), std::string("::1"), options_.listen})
        hosts_.insert(host_port(h, port_));
    loop_.start();
    started_ = true;
}

std::string Server::url() const {
    return "http://" + host_port(is_wildcard(options_.listen) ? "127.0.0.1" : options_.listen, port_) + "/";
}

void Server::stop() {
    if (stopping_.exchange(true)) return;
    loop_.stop();  // every page's connection closes: on_closed hands its session to the stopper
    pages_.stop();
    if (!started_) return;
    const ConnectionStats s = loop_.stats();
    log_line("connections: " + std::to_string(s.accepted) + " accepted, " + std::to_string(s.head_timeouts) +
             " closed for sending no request within " + std::to_string(int(options_.connections.head_timeout_s)) +
             " s, " + std::to_string(s.dropped_at_cap) + " dropped at the cap of " +
             std::to_string(loop_.max_connections()));
}

std::string Server::host_problem(const HttpRequest& r) const {
    const std::string* host = r.field("host");
    if (!host) return "no Host header";
    if (r.count("host") > 1) return "more than one Host header";
    if (any_host_ || hosts_.count(*host)) return {};
    return "Host '" + host->substr(0, 80) + "' is not this server";
}

ConnectionHandler::Answer Server::on_request(ConnId id, const HttpRequest& r, const std::string& peer) {
    if (const std::string p = host_problem(r); !p.empty()) return {http_error(403, p)};
    const bool head = r.method == "HEAD";
    if (!head && r.method != "GET") return {http_error(405, "only GET")};
    if (r.path() == "/ws") return websocket(id, r, peer);
    if (r.path() != "/") return {http_error(404, "not found: this server has one page, at /")};
    return {page_answer(head)};
}

ConnectionHandler::Answer Server::websocket(ConnId id, const HttpRequest& r, const std::string& peer) {
    if (r.method != "GET" || !r.has_token("upgrade", "websocket") || !r.has_token("connection", "upgrade"))
        return {http_error(400, "/ws is the page's WebSocket: a GET with Upgrade: websocket")};
    const std::string* version = r.field("sec-websocket-version");
    if (!version || *version != "13") return {http_error(426, "WebSocket version 13 only")};
    const std::string* key = r.field("sec-websocket-key");
    if (!key || !ws::valid_key(*key)) return {http_error(400, "no valid Sec-WebSocket-Key")};
    const std::string* origin = r.field("origin");
    if (origin && *origin != "http://" + *r.field("host")) {
        const std::string why = "Origin '" + origin->substr(0, 80) + "' is not this server's page";
        log_line("refused a WebSocket from " + peer + ": " + why);
        return {http_error(403, why)};
    }
    if (!pages_.reserve()) {
        log_line("refused a WebSocket from " + peer + ": " + std::to_string(options_.max_clients) +
                 " pages are open already");
        return {http_error(503, "too many pages open")};
    }
    pages_.add(id, peer);
    return {"HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: " +
                ws::accept_key(*key) + "\r\n\r\n",
            true};
}

void Server::on_open(ConnId id) { pages_.open(id); }

void Server::on_message(ConnId id, int opcode, std::string payload) {
    if (opcode == ws::binary) {
        loop_.close(id, ws::unsupported, "binary message (the page sends JSON text)");
        return;
    }
    std::string error;
    const auto message = parse_client_message(payload, options_.limits, &error);
    if (!message) {
        loop_.close(id, ws::policy, "bad message: " + error);
        return;
    }
    pages_.handle(id, *message);
}

void Server::on_closed(ConnId id, const CloseReason& reason) {
    if (reason.by_server && !stopping_)
        log_line(pages_.name(id) + ": closed with " + std::to_string(reason.code) + ": " + reason.why);
    pages_.closed(id);
}

}  // namespace arbor::view
