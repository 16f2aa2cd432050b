/// ConnectionLoop (view/connections.h): listening, accepting, queueing output and the loop itself;
/// reading is in connection_input.cpp, writing out, closing and deadlines in connection_closing.cpp.
#include "view/connections.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "view/connection_state.h"
#include "view/log.h"
#include "view/websocket.h"

namespace arbor::view {

namespace {

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// Deadlines are checked at least this often (seconds).
constexpr int poll_ms = 250;
/// Open files kept for everything but connections (scene, logs, TBB, the listener).
constexpr int reserved_files = 64;

std::string peer_address(const sockaddr_storage& a) {
    char buf[INET6_ADDRSTRLEN] = "?";
    if (a.ss_family == AF_INET) inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(a).sin_addr, buf, sizeof buf);
    if (a.ss_family == AF_INET6)
        inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6&>(a).sin6_addr, buf, sizeof buf);
    return buf;
}

}  // namespace

ConnectionLoop::ConnectionLoop(const ConnectionLimits& limits, ConnectionHandler& handler)
    : limits_(limits), handler_(handler), max_connections_(limits.max_connections) {}

ConnectionLoop::~ConnectionLoop() {
    stop();
    if (listen_fd_ >= 0) ::close(listen_fd_);
    if (wake_fd_ >= 0) ::close(wake_fd_);
}

int ConnectionLoop::listen(const std::string& address, int port) {
    const bool v6 = address.find(':') != std::string::npos;
    const std::string where = (v6 ? "[" + address + "]" : address) + ":" + std::to_string(port);
    sockaddr_storage sa{};
    socklen_t len = 0;
    if (v6) {
        auto& s6 = reinterpret_cast<sockaddr_in6&>(sa);
        s6.sin6_family = AF_INET6;
        s6.sin6_port = htons(std::uint16_t(port));
        if (inet_pton(AF_INET6, address.c_str(), &s6.sin6_addr) != 1)
            throw std::runtime_error("cannot listen on " + where + " (not a numeric IPv6 address)");
        len = sizeof s6;
    } else {
        auto& s4 = reinterpret_cast<sockaddr_in&>(sa);
        s4.sin_family = AF_INET;
        s4.sin_port = htons(std::uint16_t(port));
        if (inet_pton(AF_INET, address.c_str(), &s4.sin_addr) != 1)
            throw std::runtime_error("cannot listen on " + where + " (not a numeric IPv4 address)");
        len = sizeof s4;
    }
    const int fd = ::socket(sa.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) throw std::runtime_error("cannot listen on " + where + " (" + std::strerror(errno) + ")");
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);  // a restart need not wait for TIME_WAIT
    if (::bind(fd, reinterpret_cast<sockaddr*>(&sa), len) != 0 || ::listen(fd, 128) != 0) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        throw std::runtime_error("cannot listen on " + where + " (" + why + ")");
    }
    sockaddr_storage bound{};
    socklen_t blen = sizeof bound;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &blen);
    listen_fd_ = fd;
    wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (wake_fd_ < 0) throw std::runtime_error(std::string("eventfd: ") + std::strerror(errno));
    rlimit files{};
    if (::getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur != RLIM_INFINITY &&
        rlim_t(max_connections_) + reserved_files > files.rlim_cur) {
        max_connections_ = std::max(1, int(files.rlim_cur) - reserved_files);
        log_line("at most " + std::to_string(max_connections_) + " connections (the open-file limit is " +
                 std::to_string(files.rlim_cur) + ")");
    }
    return ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6&>(bound).sin6_port
                                             : reinterpret_cast<sockaddr_in&>(bound).sin_port);
}

void ConnectionLoop::start() {
    thread_ = std::thread([this] { run(); });
}

void ConnectionLoop::wake() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof one);  // full counter: a wake is pending anyway
}

void ConnectionLoop::stop() {
    if (!thread_.joinable()) return;
    stopping_ = true;
    wake();
    thread_.join();
    std::vector<ConnId> pages;
    {
        const std::lock_guard lock(mutex_);
        for (auto& [id, c] : conns_) {
            if (c->state == ConnState::websocket) {
                // Best effort: what fits in the socket's buffer now; the page learns why it ends.
                std::string bye = c->out.substr(c->out_sent);
                ws::append_close(bye, ws::going_away, "the server is stopping");
                [[maybe_unused]] const auto n = ::send(c->fd, bye.data(), bye.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
                pages.push_back(id);
            }
            ::close(c->fd);
        }
        conns_.clear();
        close_requests_.clear();
        stats_.open = 0;
    }
    for (const ConnId id : pages) handler_.on_closed(id, {ws::going_away, "the server is stopping", true});
}

bool ConnectionLoop::send(ConnId id, int opcode, std::string_view payload) {
    bool queued = false;
    {
        const std::lock_guard lock(mutex_);
        const auto it = conns_.find(id);
        if (it == conns_.end() || !it->second->accepting) return false;
        Conn& c = *it->second;
        if (c.pending() + payload.size() + 14 > limits_.max_output_bytes) {
            c.accepting = false;
            c.abort = true;
            c.close_request =
                CloseReason{ws::going_away,
                            "more than " + std::to_string(limits_.max_output_bytes) + " bytes of output unread", true};
            close_requests_.push_back(id);
        } else {
            if (c.pending() == 0) {
                c.out.clear(), c.out_sent = 0;
                c.out_since = now_s();
            }
            ws::append_frame(c.out, opcode, payload);
            queued = true;
        }
    }
    wake();
    return queued;
}

void ConnectionLoop::close(ConnId id, int code, std::string_view why) {
    {
        const std::lock_guard lock(mutex_);
        const auto it = conns_.find(id);
        if (it == conns_.end() || !it->second->accepting) return;
        Conn& c = *it->second;
        if (c.pending() == 0) c.out_since = now_s();
        ws::append_close(c.out, code, why);
        c.accepting = false;
        c.close_request = CloseReason{code, std::string(why), true};
        close_requests_.push_back(id);
    }
    wake();
}

ConnectionStats ConnectionLoop::stats() const {
    const std::lock_guard lock(mutex_);
    ConnectionStats s = stats_;
    s.open = conns_.size();
    return s;
}

void ConnectionLoop::queue(Conn& c, std::string_view bytes, bool last) {
    const std::lock_guard lock(mutex_);
    if (c.pending() == 0) {
        c.out.clear(), c.out_sent = 0;
        c.out_since = now_s();
    }
    c.out.append(bytes);
    if (last) c.accepting = false;
}

void ConnectionLoop::run() {
    std::vector<pollfd> fds;
    std::vector<ConnId> ids;
    while (!stopping_) {
        fds.clear(), ids.clear();
        fds.push_back({wake_fd_, POLLIN, 0});
        fds.push_back({listen_fd_, short(now_s() >= accept_paused_until_ ? POLLIN : 0), 0});
        {
            const std::lock_guard lock(mutex_);
            for (const auto& [id, c] : conns_) {
                short events = 0;
                // A WebSocket's buffer always has room: the reader takes each complete frame.
                if (c->state != ConnState::head || c->in.size() < max_head_bytes) events |= POLLIN;
                if (c->pending() > 0 && !c->write_shut) events |= POLLOUT;
                fds.push_back({c->fd, events, 0});
                ids.push_back(id);
            }
        }
        if (::poll(fds.data(), fds.size(), poll_ms) < 0 && errno != EINTR) {
            log_line(std::string("poll: ") + std::strerror(errno));
            accept_paused_until_ = now_s() + 0.1;
        }
        const double now = now_s();
        if (fds[0].revents & POLLIN) {
            std::uint64_t n = 0;
            [[maybe_unused]] const auto r = ::read(wake_fd_, &n, sizeof n);
        }
        for (std::size_t i = 0; i < ids.size(); ++i) {
            const short ev = fds[i + 2].revents;
            if (!ev) continue;
            auto it = conns_.find(ids[i]);  // the loop thread reads the table without the lock
            if (it == conns_.end()) continue;
            if (ev & (POLLIN | POLLHUP | POLLERR)) on_readable(ids[i], *it->second, now);
            it = conns_.find(ids[i]);
            if (it != conns_.end() && (ev & POLLOUT)) on_writable(ids[i], *it->second, now);
        }
        if (fds[1].revents & POLLIN) accept_new(now);
        take_close_requests();
        check_deadlines(now_s());
    }
}

void ConnectionLoop::accept_new(double now) {
    for (int k = 0; k < 64; ++k) {  // a bounded batch: connections already open get their turn
        sockaddr_storage sa{};
        socklen_t len = sizeof sa;
        const int fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
            if (errno == EINTR || errno == ECONNABORTED) continue;
            if (errno == EMFILE || errno == ENFILE) {
                // Out of files below our own cap (other files are open): make room, or wait a little.
                if (drop_oldest_idle()) continue;
                if (!cap_logged_) log_line("out of open files: new connections wait");
                cap_logged_ = true;
            } else if (errno != EAGAIN && errno != EWOULDBLOCK) {
                log_line(std::string("accept: ") + std::strerror(errno));
            }
            if (errno != EAGAIN && errno != EWOULDBLOCK) accept_paused_until_ = now + 0.1;
            return;
        }
        if (conns_.size() >= std::size_t(max_connections_)) {
            if (!cap_logged_)
                log_line("at the cap of " + std::to_string(max_connections_) +
                         " connections: the oldest idle ones are dropped for new ones");
            cap_logged_ = true;
            if (!drop_oldest_idle()) {
                ::close(fd);
                const std::lock_guard lock(mutex_);
                ++stats_.dropped_at_cap;
                continue;
            }
        }
        const int one = 1;
        // A frame leaves as a header and a payload: with Nagle's algorithm the last partial segment
        // waited for the page's delayed ACK, about 40 ms a frame.
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        auto c = std::make_unique<Conn>(limits_.max_message_bytes);
        c->fd = fd;
        c->peer = peer_address(sa);
        c->opened = c->last_input = now;
        const std::lock_guard lock(mutex_);
        conns_.emplace(next_id_++, std::move(c));
        ++stats_.accepted;
    }
}

bool ConnectionLoop::drop_oldest_idle() {
    for (const ConnState wanted : {ConnState::closing, ConnState::head}) {
        for (const auto& [id, c] : conns_) {
            if (c->state != wanted) continue;
            {
                const std::lock_guard lock(mutex_);
                ++stats_.dropped_at_cap;
            }
            drop(id, {});
            return true;
        }
    }
    return false;
}

}  // namespace arbor::view
