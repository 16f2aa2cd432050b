#pragma once
/// One connection's state in ConnectionLoop (view/connections.h): shared by the loop's files
/// (connections.cpp: listening, accepting, sending; connection_input.cpp: reading heads and
/// frames; connection_closing.cpp: writing out, closing, deadlines). Private to view/.
#include "view/connections.h"
#include "view/websocket.h"

#include <optional>
#include <string>

namespace arbor::view {

enum class ConnState { head, websocket, closing };

struct ConnectionLoop::Conn {
    explicit Conn(std::size_t max_message) : reader(max_message) {}
    // Loop thread only.
    int fd = -1;
    std::string peer;
    ConnState state = ConnState::head;
    double opened = 0, last_input = 0, linger_end = 0;
    bool ping_sent = false, write_shut = false;
    std::string in;  ///< bytes read and not yet used: at most max_head_bytes or one frame
    ws::MessageReader reader;
    // Under mutex_.
    std::string out;  ///< queued output; out_sent bytes of it are written
    std::size_t out_sent = 0;
    double out_since = 0;   ///< when the output last moved or was queued onto an empty queue
    bool accepting = true;  ///< send() may queue (false once an answer or a close frame is queued)
    bool abort = false;     ///< drop at once instead of closing gracefully (too much output unread)
    std::optional<CloseReason> close_request;
    std::size_t pending() const { return out.size() - out_sent; }
};

}  // namespace arbor::view
