#include "view/websocket.h"

#include <cstdint>

#include "view/sha1.h"

namespace arbor::view::ws {

namespace {

Event fail(int code, std::string why) {
    Event e;
    e.kind = Event::error;
    e.code = code;
    e.why = std::move(why);
    return e;
}

}  // namespace

bool valid_key(std::string_view key) {
    if (key.size() != 24 || key.substr(22) != "==") return false;
    for (const char c : key.substr(0, 22)) {
        const bool ok =
            (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/';
        if (!ok) return false;
    }
    return true;
}

std::string accept_key(std::string_view key) {
    const auto digest = sha1(std::string(key) + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11");
    return base64(std::string_view(reinterpret_cast<const char*>(digest.data()), digest.size()));
}

void append_frame(std::string& out, int opcode, std::string_view payload) {
    const std::uint64_t n = payload.size();
    out.push_back(char(0x80 | (opcode & 0x0F)));
    if (n < 126) {
        out.push_back(char(n));
    } else if (n < 65536) {
        out.push_back(char(126));
        out.push_back(char((n >> 8) & 0xFF));
        out.push_back(char(n & 0xFF));
    } else {
        out.push_back(char(127));
        for (int i = 7; i >= 0; --i) out.push_back(char((n >> (8 * i)) & 0xFF));
    }
    out.append(payload);
}

void append_close(std::string& out, int code, std::string_view why) {
    std::string payload{char((code >> 8) & 0xFF), char(code & 0xFF)};
    payload += why.substr(0, 123);
    append_frame(out, close, payload);
}

Event MessageReader::next(std::string& buf) {
    for (;;) {
        if (buf.size() < 2) return {};
        const auto b0 = std::uint8_t(buf[0]), b1 = std::uint8_t(buf[1]);
        const bool fin = (b0 & 0x80) != 0;
        const int op = b0 & 0x0F;
        if (b0 & 0x70) return fail(protocol_error, "reserved bits set (no extension was agreed)");
        if (!(b1 & 0x80)) return fail(protocol_error, "an unmasked frame from the page");
        std::size_t header = 2;
        std::uint64_t n = b1 & 0x7F;
        if (n == 126 || n == 127) {
            const std::size_t bytes = n == 126 ? 2 : 8;
            if (buf.size() < 2 + bytes) return {};
            n = 0;
            for (std::size_t i = 0; i < bytes; ++i) n = (n << 8) | std::uint8_t(buf[2 + i]);
            if (n >> 63) return fail(protocol_error, "frame length with its top bit set");
            header += bytes;
        }
        header += 4;  // the mask
        const bool is_control = (op & 0x8) != 0;
        if (is_control) {
            if (op != close && op != ping && op != pong)
                return fail(protocol_error, "unknown opcode " + std::to_string(op));
            if (!fin) return fail(protocol_error, "a fragmented control frame");
            if (n > 125) return fail(protocol_error, "a control frame longer than 125 bytes");
        } else {
            if (op != continuation && op != text && op != binary)
                return fail(protocol_error, "unknown opcode " + std::to_string(op));
            if (op != continuation && message_op_ >= 0)
                return fail(protocol_error, "a new message inside a fragmented one");
            if (op == continuation && message_op_ < 0) return fail(protocol_error, "a continuation without a message");
            const std::uint64_t before = op == continuation ? message_.size() : 0;
            if (n > max_ || before + n > max_)
                return fail(too_big, "message longer than " + std::to_string(max_) + " bytes");
        }
        if (buf.size() < header + n) return {};
        std::string payload = buf.substr(header, std::size_t(n));
        const char* mask = buf.data() + header - 4;
        for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = char(payload[i] ^ mask[i & 3]);
        buf.erase(0, header + std::size_t(n));
        if (is_control) {
            Event e;
            e.kind = Event::control;
            e.opcode = op;
            if (op == close) {
                if (payload.size() == 1) return fail(protocol_error, "a close frame of 1 byte");
                e.code = payload.size() >= 2 ? (std::uint8_t(payload[0]) << 8) | std::uint8_t(payload[1]) : 1005;
                e.why = payload.size() > 2 ? payload.substr(2) : std::string();
            }
            e.payload = std::move(payload);
            return e;
        }
        if (op != continuation) message_op_ = op, message_.clear();
        message_ += payload;
        if (!fin) continue;
        Event e;
        e.kind = Event::message;
        e.opcode = message_op_;
        e.payload = std::move(message_);
        message_.clear();
        message_op_ = -1;
        return e;
    }
}

}  // namespace arbor::view::ws
