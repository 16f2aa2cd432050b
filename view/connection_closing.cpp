/// ConnectionLoop's closing side: queued output written out, close requests taken, the
/// deadlines (handshake, idle, unread output, lingering close) and dropping a connection.
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

#include "view/connection_state.h"
#include "view/log.h"

namespace arbor::view {

void ConnectionLoop::begin_closing(ConnId id, Conn& c, const CloseReason& reason) {
    c.state = ConnState::closing;
    c.in.clear();
    handler_.on_closed(id, reason);
}

void ConnectionLoop::on_writable(ConnId id, Conn& c, double now) {
    int failed = 0;
    {
        const std::lock_guard lock(mutex_);
        if (c.pending() == 0) return;
        const ssize_t n = ::send(c.fd, c.out.data() + c.out_sent, c.pending(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            c.out_sent += std::size_t(n);
            c.out_since = now;
            if (c.pending() == 0)
                c.out.clear(), c.out_sent = 0;
            else if (c.out_sent > (std::size_t(1) << 20))
                c.out.erase(0, c.out_sent), c.out_sent = 0;
        } else if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            failed = errno;
        }
    }
    if (failed) drop(id, {0, std::strerror(failed), false});
}

void ConnectionLoop::take_close_requests() {
    std::vector<ConnId> ids;
    {
        const std::lock_guard lock(mutex_);
        ids.swap(close_requests_);
    }
    for (const ConnId id : ids) {
        const auto it = conns_.find(id);
        if (it == conns_.end()) continue;
        Conn& c = *it->second;
        std::optional<CloseReason> reason;
        bool abort = false;
        {
            const std::lock_guard lock(mutex_);
            reason.swap(c.close_request);
            abort = c.abort;
        }
        if (!reason) continue;
        if (abort)
            drop(id, *reason);
        else if (c.state == ConnState::websocket)
            begin_closing(id, c, *reason);
    }
}

void ConnectionLoop::check_deadlines(double now) {
    std::vector<std::pair<ConnId, CloseReason>> drops;
    std::vector<ConnId> timed_out;
    for (auto& [id, cp] : conns_) {
        Conn& c = *cp;
        std::size_t pending = 0;
        double out_since = 0;
        {
            const std::lock_guard lock(mutex_);
            pending = c.pending();
            out_since = c.out_since;
        }
        const bool stuck = pending > 0 && now - out_since > limits_.write_timeout_s;
        switch (c.state) {
            case ConnState::head:
                if (now - c.opened > limits_.head_timeout_s) timed_out.push_back(id);
                break;
            case ConnState::websocket:
                if (stuck) {
                    drops.push_back(
                        {id,
                         {ws::going_away,
                          "its output did not move for " + std::to_string(int(limits_.write_timeout_s)) + " s", true}});
                } else if (now - c.last_input > limits_.idle_timeout_s) {
                    drops.push_back(
                        {id,
                         {ws::going_away, "nothing received for " + std::to_string(int(limits_.idle_timeout_s)) + " s",
                          true}});
                } else if (now - c.last_input > limits_.ping_after_s && !c.ping_sent) {
                    std::string ping;
                    ws::append_frame(ping, ws::ping, "");
                    queue(c, ping, false);
                    c.ping_sent = true;
                }
                break;
            case ConnState::closing:
                if (!c.write_shut && pending == 0) {
                    ::shutdown(c.fd, SHUT_WR);
                    c.write_shut = true;
                    c.linger_end = now + limits_.linger_s;
                } else if ((c.write_shut && now > c.linger_end) || stuck) {
                    drops.push_back({id, {}});
                }
                break;
        }
    }
    if (!timed_out.empty()) {
        const std::lock_guard lock(mutex_);
        stats_.head_timeouts += timed_out.size();
    }
    for (const ConnId id : timed_out) drop(id, {});
    for (const auto& [id, reason] : drops) drop(id, reason);
}

void ConnectionLoop::drop(ConnId id, const CloseReason& reason) {
    const auto it = conns_.find(id);
    if (it == conns_.end()) return;
    const bool page = it->second->state == ConnState::websocket;
    {
        const std::lock_guard lock(mutex_);
        ::close(it->second->fd);
        conns_.erase(it);
    }
    if (page) handler_.on_closed(id, reason);
}

}  // namespace arbor::view
