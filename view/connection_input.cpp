/// ConnectionLoop's reading side: bytes from a socket, the HTTP head (a page, or the upgrade to
/// a WebSocket) and WebSocket frames handed to the handler.
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "view/connection_state.h"
#include "view/log.h"

namespace arbor::view {

void ConnectionLoop::on_readable(ConnId id, Conn& c, double now) {
    char buf[16384];
    std::size_t room = sizeof buf;
    if (c.state == ConnState::head) room = std::min(room, max_head_bytes - c.in.size());
    if (c.state == ConnState::websocket) room = std::min(room, c.reader.buffer_bytes() - c.in.size());
    if (room == 0) return;  // not polled for input while full; a hang-up is read once there is room
    const ssize_t n = ::recv(c.fd, buf, room, 0);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    if (n <= 0) {  // the peer closed (or reset) its side
        drop(id, {0, n == 0 ? "the connection ended" : std::strerror(errno), false});
        return;
    }
    if (c.state == ConnState::closing) return;  // lingering: input is thrown away
    c.in.append(buf, std::size_t(n));
    c.last_input = now;
    c.ping_sent = false;
    if (c.state == ConnState::head)
        on_head(id, c, now);
    else
        on_frames(id, c);
}

void ConnectionLoop::on_head(ConnId id, Conn& c, double now) {
    const std::size_t len = head_length(c.in);
    if (len == 0) {
        if (c.in.size() >= max_head_bytes) {
            queue(c, http_error(431, "request head longer than " + std::to_string(max_head_bytes) + " bytes"), true);
            c.state = ConnState::closing;
        }
        return;
    }
    int status = 400;
    std::string why;
    const auto request = parse_request_head(std::string_view(c.in).substr(0, len), &status, &why);
    if (!request) {
        queue(c, http_error(status, why), true);
        c.state = ConnState::closing;
        return;
    }
    c.in.erase(0, len);
    const ConnectionHandler::Answer answer = handler_.on_request(id, *request, c.peer);
    queue(c, answer.bytes, !answer.upgrade);
    if (!answer.upgrade) {
        c.state = ConnState::closing;
        return;
    }
    c.state = ConnState::websocket;
    c.last_input = now;
    handler_.on_open(id);
    on_frames(id, c);  // frames that came right behind the head
}

void ConnectionLoop::on_frames(ConnId id, Conn& c) {
    while (c.state == ConnState::websocket) {
        {
            const std::lock_guard lock(mutex_);
            if (!c.accepting) return;  // closing (close() was called): take_close_requests finishes it
        }
        ws::Event e = c.reader.next(c.in);
        switch (e.kind) {
            case ws::Event::need_more:
                return;
            case ws::Event::error: {
                std::string frame;
                ws::append_close(frame, e.code, e.why);
                queue(c, frame, true);
                begin_closing(id, c, {e.code, e.why, true});
                return;
            }
            case ws::Event::control:
                if (e.opcode == ws::ping) {
                    std::string frame;
                    ws::append_frame(frame, ws::pong, e.payload);
                    queue(c, frame, false);
                } else if (e.opcode == ws::close) {
                    // Echo the page's code (RFC 6455 5.5.1); 1005 means it sent none, and is never sent.
                    std::string frame;
                    ws::append_close(frame, e.code == 1005 ? ws::normal : e.code, "");
                    queue(c, frame, true);
                    begin_closing(id, c, {e.code, e.why, false});
                    return;
                }
                break;
            case ws::Event::message:
                handler_.on_message(id, e.opcode, std::move(e.payload));
                break;
        }
    }
}

}  // namespace arbor::view
