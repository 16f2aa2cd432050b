#pragma once
/// The server side of RFC 6455 for `arbor view`: the handshake's accept key, the reading of the
/// page's frames (masked, joined into messages, bounded) and the writing of the server's frames.
/// No extension is agreed, so every reserved bit must be zero.
#include <cstddef>
#include <string>
#include <string_view>

namespace arbor::view::ws {

enum Opcode : int { continuation = 0x0, text = 0x1, binary = 0x2, close = 0x8, ping = 0x9, pong = 0xA };

/// RFC 6455 7.4.1 close codes.
enum CloseCode : int {
    normal = 1000,
    going_away = 1001,
    protocol_error = 1002,
    unsupported = 1003,
    policy = 1008,
    too_big = 1009
};

/// Whether `key` is a Sec-WebSocket-Key: base64 of 16 bytes (24 characters).
bool valid_key(std::string_view key);
/// The Sec-WebSocket-Accept answering `key`: base64(SHA-1(key + the RFC's GUID)).
std::string accept_key(std::string_view key);

/// Appends one unfragmented server frame (unmasked) holding `payload` to `out`.
void append_frame(std::string& out, int opcode, std::string_view payload);
/// Appends a close frame: the code, then `why` cut to fit a control frame (125 bytes).
void append_close(std::string& out, int code, std::string_view why);

/// What MessageReader::next found.
struct Event {
    enum Kind { need_more, message, control, error } kind = need_more;
    int opcode = 0;       ///< message: text or binary; control: close, ping or pong
    std::string payload;  ///< unmasked; a message's fragments joined
    int code = 0;         ///< error: the close code to answer; control close: the page's code (1005: none)
    std::string why;      ///< error: one line
};

/// Joins the page's frames into messages of at most `max_message` bytes. A frame announcing more
/// is refused (1009) from its header, before its payload arrives, so a connection never buffers
/// more than buffer_bytes().
class MessageReader {
public:
    explicit MessageReader(std::size_t max_message) : max_(max_message) {}
    /// Takes frames from the front of `buf` (erasing them) until a message or control frame is
    /// complete, a frame is bad (then the connection must be closed with `code`), or more bytes
    /// are needed.
    Event next(std::string& buf);
    /// The most bytes worth buffering: one frame's header and the largest payload accepted.
    std::size_t buffer_bytes() const { return 14 + (max_ > 125 ? max_ : 125); }

private:
    std::size_t max_;
    std::string message_;  ///< the fragments so far
    int message_op_ = -1;  ///< its opcode, -1 between messages
};

}  // namespace arbor::view::ws
