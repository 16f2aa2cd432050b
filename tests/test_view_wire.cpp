// What the viewer's server reads from the network before any policy (view/http.h,
// view/websocket.h, view/sha1.h): request heads parse to their fields or are refused with a
// status; the page's frames join into messages, are refused with their close code (1009 from a
// header alone, before the payload), and read the same fed a byte at a time; the handshake key
// matches RFC 6455's example.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <vector>

#include "view/http.h"
#include "view/sha1.h"
#include "view/websocket.h"

using namespace arbor::view;

namespace {

std::string hex(const std::array<std::uint8_t, 20>& d) {
    static const char* digits = "0123456789abcdef";
    std::string s;
    for (auto b : d) s += digits[b >> 4], s += digits[b & 15];
    return s;
}

/// A frame as a page sends it: masked, `announced` (default: the payload's size) in its header.
std::string masked(int opcode, const std::string& payload, bool fin = true, std::uint64_t announced = ~0ull) {
    const std::uint64_t n = announced == ~0ull ? payload.size() : announced;
    std::string f(1, char((fin ? 0x80 : 0) | opcode));
    if (n < 126) {
        f += char(0x80 | n);
    } else if (n < 65536) {
        f += char(0x80 | 126), f += char(n >> 8), f += char(n & 0xFF);
    } else {
        f += char(0x80 | 127);
        for (int i = 7; i >= 0; --i) f += char((n >> (8 * i)) & 0xFF);
    }
    const char mask[4] = {0x12, 0x34, 0x56, 0x78};
    f.append(mask, 4);
    for (std::size_t i = 0; i < payload.size(); ++i) f += char(payload[i] ^ mask[i & 3]);
    return f;
}

ws::Event read_one(std::string bytes, std::size_t max = 4096) {
    ws::MessageReader r(max);
    return r.next(bytes);
}

HttpRequest parsed(const std::string& head) {
    int status = 0;
    std::string why;
    const auto r = parse_request_head(head, &status, &why);
    REQUIRE_MESSAGE(r, why);
    return *r;
}

int refused(const std::string& head) {
    int status = 0;
    std::string why;
    CHECK_FALSE(parse_request_head(head, &status, &why));
    CHECK(!why.empty());
    return status;
}

}  // namespace

TEST_CASE("view wire: SHA-1, base64 and the handshake key") {
    CHECK(hex(sha1("")) == "da39a3ee5e6b4b0d3255bfef95601890afd80709");
    CHECK(hex(sha1("abc")) == "a9993e364706816aba3e25717850c26c9cd0d89d");
    CHECK(hex(sha1("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")) ==
          "84983e441c3bd26ebaae4aa1f95129e5e54670f1");  // 56 bytes: the length spills into a second block
    CHECK(base64("") == "");
    CHECK(base64("f") == "Zg==");
    CHECK(base64("fo") == "Zm8=");
    CHECK(base64("foobar") == "Zm9vYmFy");
    CHECK(ws::accept_key("dGhlIHNhbXBsZSBub25jZQ==") == "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");  // RFC 6455 1.3
    CHECK(ws::valid_key("dGhlIHNhbXBsZSBub25jZQ=="));
    CHECK_FALSE(ws::valid_key("dGhlIHNhbXBsZSBub25jZQ="));
    CHECK_FALSE(ws::valid_key("dGhlIHNhbXBsZSBub25j!Q=="));
}

TEST_CASE("view wire: a request head parses to its fields") {
    CHECK(head_length("GET / HTTP/1.1\r\nHost: a\r\n") == 0);
    CHECK(head_length("GET / HTTP/1.1\r\nHost: a\r\n\r\nrest") == 27);
    CHECK(head_length("GET / HTTP/1.1\nHost: a\n\nrest") == 24);
    const HttpRequest r = parsed(
        "GET /ws?x=1 HTTP/1.1\r\nHost:  127.0.0.1:8080 \r\nConnection: keep-alive, Upgrade\r\nUPGRADE: "
        "WebSocket\r\n\r\n");
    CHECK(r.method == "GET");
    CHECK(r.target == "/ws?x=1");
    CHECK(r.path() == "/ws");
    CHECK(r.version == "HTTP/1.1");
    REQUIRE(r.field("host"));
    CHECK(*r.field("host") == "127.0.0.1:8080");
    CHECK(r.has_token("connection", "upgrade"));
    CHECK(r.has_token("upgrade", "websocket"));
    CHECK_FALSE(r.has_token("connection", "close"));
    CHECK(r.field("origin") == nullptr);
    CHECK(parsed("GET / HTTP/1.0\n\n").fields.empty());
}

TEST_CASE("view wire: malformed request heads are refused with a status") {
    CHECK(refused("\r\n\r\n") == 400);
    CHECK(refused("GET /\r\n\r\n") == 400);
    CHECK(refused("GET / HTTP/2.0\r\n\r\n") == 400);
    CHECK(refused("G(T / HTTP/1.1\r\n\r\n") == 400);
    CHECK(refused("GET / HTTP/1.1\r\nHost : a\r\n\r\n") == 400);  // space before the colon
    CHECK(refused("GET / HTTP/1.1\r\nHost: a\r\n folded\r\n\r\n") == 400);
    CHECK(refused("GET / HTTP/1.1\r\nno colon\r\n\r\n") == 400);
    CHECK(refused(std::string("GET / HTTP/1.1\r\nX: a\x01\r\n\r\n")) == 400);
    std::string many = "GET / HTTP/1.1\r\n";
    for (std::size_t i = 0; i <= max_header_fields; ++i) many.append("X").append(std::to_string(i)).append(": 1\r\n");
    CHECK(refused(many + "\r\n") == 431);
    CHECK(refused("GET / HTTP/1.1\r\nX: " + std::string(max_head_bytes, 'a') + "\r\n\r\n") == 431);
    const std::string answer = http_error(405, "only GET");
    CHECK(answer.rfind("HTTP/1.1 405 Method Not Allowed\r\n", 0) == 0);
    CHECK(answer.find("Connection: close\r\n") != std::string::npos);
}

TEST_CASE("view wire: the page's frames join into messages") {
    const ws::Event text = read_one(masked(ws::text, R"({"type":"ack","frame":1})"));
    CHECK(text.kind == ws::Event::message);
    CHECK(text.opcode == ws::text);
    CHECK(text.payload == R"({"type":"ack","frame":1})");

    // Fragments with a ping between them, then a close with its code.
    std::string bytes = masked(ws::text, "ab", false) + masked(ws::ping, "p") + masked(ws::continuation, "cd", false) +
                        masked(ws::continuation, "e") + masked(ws::close, std::string("\x03\xe8", 2) + "bye");
    const std::string whole = bytes;
    ws::MessageReader r(4096);
    ws::Event e = r.next(bytes);
    CHECK(e.kind == ws::Event::control);
    CHECK(e.opcode == ws::ping);
    CHECK(e.payload == "p");
    e = r.next(bytes);
    CHECK(e.kind == ws::Event::message);
    CHECK(e.payload == "abcde");
    e = r.next(bytes);
    CHECK(e.kind == ws::Event::control);
    CHECK(e.opcode == ws::close);
    CHECK(e.code == 1000);
    CHECK(e.why == "bye");
    CHECK(bytes.empty());
    CHECK(r.next(bytes).kind == ws::Event::need_more);

    // Fed a byte at a time: the same events, in the same order.
    ws::MessageReader slow(4096);
    std::string buf;
    std::vector<int> kinds;
    for (const char c : whole) {
        buf += c;
        for (ws::Event x = slow.next(buf); x.kind != ws::Event::need_more; x = slow.next(buf)) kinds.push_back(x.kind);
    }
    CHECK(kinds == std::vector<int>{ws::Event::control, ws::Event::message, ws::Event::control});

    // Lengths in 16 and 64 bits.
    std::string mid = masked(ws::text, std::string(300, 'x'));
    CHECK(read_one(mid).payload.size() == 300);
    CHECK(read_one(masked(ws::binary, std::string(70000, 'y')), 100000).payload.size() == 70000);
}

TEST_CASE("view wire: bad frames are refused with their close code") {
    auto code = [](const std::string& bytes, std::size_t max = 4096) {
        const ws::Event e = read_one(bytes, max);
        CHECK(e.kind == ws::Event::error);
        CHECK(!e.why.empty());
        return e.code;
    };
    // Too long, known from the header alone (no payload sent).
    CHECK(code(masked(ws::text, "", true, 5000).substr(0, 8)) == ws::too_big);
    CHECK(code(masked(ws::text, "", true, 1ull << 40).substr(0, 14)) == ws::too_big);
    CHECK(code(masked(ws::text, std::string(3000, 'a'), false) +
               masked(ws::continuation, "", true, 2000).substr(0, 8)) == ws::too_big);
    CHECK(read_one(masked(ws::text, "", true, 5000).substr(0, 3)).kind == ws::Event::need_more);  // length incomplete
    std::string unmasked = masked(ws::text, "hi");
    unmasked[1] = char(unmasked[1] & 0x7F);
    CHECK(code(unmasked) == ws::protocol_error);
    std::string reserved = masked(ws::text, "hi");
    reserved[0] = char(reserved[0] | 0x40);
    CHECK(code(reserved) == ws::protocol_error);
    CHECK(code(masked(ws::ping, std::string(126, 'p'))) == ws::protocol_error);
    CHECK(code(masked(ws::ping, "p", false)) == ws::protocol_error);
    CHECK(code(masked(0x3, "x")) == ws::protocol_error);
    CHECK(code(masked(0xB, "x")) == ws::protocol_error);
    CHECK(code(masked(ws::continuation, "x")) == ws::protocol_error);
    CHECK(code(masked(ws::text, "a", false) + masked(ws::text, "b")) == ws::protocol_error);
    CHECK(code(masked(ws::close, "x")) == ws::protocol_error);  // a 1-byte close payload
    CHECK(code(masked(ws::text, "", true, (1ull << 63) + 1).substr(0, 14)) == ws::protocol_error);
}

TEST_CASE("view wire: the server's frames") {
    std::string out;
    ws::append_frame(out, ws::text, "hi");
    CHECK(out == std::string("\x81\x02hi", 4));
    out.clear();
    ws::append_frame(out, ws::binary, std::string(126, 'x'));
    CHECK(out.substr(0, 4) == std::string("\x82\x7e\x00\x7e", 4));
    out.clear();
    ws::append_frame(out, ws::binary, std::string(65536, 'x'));
    CHECK(out.substr(0, 10) == std::string("\x82\x7f\x00\x00\x00\x00\x00\x01\x00\x00", 10));
    out.clear();
    ws::append_close(out, 1009, std::string(200, 'w'));
    CHECK(out.size() == 2 + 125);  // a control frame's payload: at most 125 bytes
    CHECK(out.substr(0, 4) == std::string("\x88\x7d\x03\xf1", 4));
}
