#include "view/http.h"

#include <algorithm>

namespace arbor::view {

namespace {

char lower(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }

bool iequal(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (lower(a[i]) != lower(b[i])) return false;
    return true;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

/// RFC 9110 5.6.2 token characters (method and field names).
bool is_token(std::string_view s) {
    if (s.empty()) return false;
    for (const char c : s) {
        const bool alnum = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
        if (!alnum && std::string_view("!#$%&'*+-.^_`|~").find(c) == std::string_view::npos) return false;
    }
    return true;
}

/// Visible ASCII and (for field values) tabs and spaces; bytes >= 0x80 are let through as opaque.
bool printable(std::string_view s, bool spaces) {
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u == 0x7F || (u < 0x20 && !(spaces && u == '\t')) || (u == ' ' && !spaces)) return false;
    }
    return true;
}

}  // namespace

const std::string* HttpRequest::field(std::string_view lower_name) const {
    for (const auto& [name, value] : fields)
        if (name == lower_name) return &value;
    return nullptr;
}

std::size_t HttpRequest::count(std::string_view lower_name) const {
    return std::size_t(
        std::count_if(fields.begin(), fields.end(), [&](const auto& f) { return f.first == lower_name; }));
}

bool HttpRequest::has_token(std::string_view lower_name, std::string_view token) const {
    for (const auto& [name, value] : fields) {
        if (name != lower_name) continue;
        std::string_view rest = value;
        while (!rest.empty()) {
            const std::size_t comma = rest.find(',');
            if (iequal(trim(rest.substr(0, comma)), token)) return true;
            if (comma == std::string_view::npos) break;
            rest.remove_prefix(comma + 1);
        }
    }
    return false;
}

std::string_view HttpRequest::path() const { return std::string_view(target).substr(0, target.find('?')); }

std::size_t head_length(std::string_view bytes) {
    for (std::size_t i = bytes.find('\n'); i != std::string_view::npos; i = bytes.find('\n', i + 1)) {
        if (i + 1 < bytes.size() && bytes[i + 1] == '\n') return i + 2;
        if (i + 2 < bytes.size() && bytes[i + 1] == '\r' && bytes[i + 2] == '\n') return i + 3;
    }
    return 0;
}

std::optional<HttpRequest> parse_request_head(std::string_view head, int* status, std::string* why) {
    auto bad = [&](int s, std::string w) -> std::optional<HttpRequest> {
        if (status) *status = s;
        if (why) *why = std::move(w);
        return std::nullopt;
    };
    if (head.size() > max_head_bytes)
        return bad(431, "request head longer than " + std::to_string(max_head_bytes) + " bytes");
    std::vector<std::string_view> lines;
    while (!head.empty()) {
        std::size_t nl = head.find('\n');
        std::string_view line = head.substr(0, nl);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.empty()) break;  // the blank line ends the head
        lines.push_back(line);
        if (nl == std::string_view::npos) break;
        head.remove_prefix(nl + 1);
    }
    if (lines.empty()) return bad(400, "empty request");
    HttpRequest r;
    const std::string_view first = lines[0];
    const std::size_t sp1 = first.find(' '), sp2 = first.rfind(' ');
    if (sp1 == std::string_view::npos || sp2 == sp1) return bad(400, "malformed request line");
    const std::string_view method = first.substr(0, sp1), target = first.substr(sp1 + 1, sp2 - sp1 - 1),
                           version = first.substr(sp2 + 1);
    if (!is_token(method)) return bad(400, "malformed method");
    if (target.empty() || !printable(target, false)) return bad(400, "malformed request target");
    if (version != "HTTP/1.1" && version != "HTTP/1.0") return bad(400, "not HTTP/1.0 or HTTP/1.1");
    r.method = method, r.target = target, r.version = version;
    if (lines.size() - 1 > max_header_fields)
        return bad(431, "more than " + std::to_string(max_header_fields) + " header fields");
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::string_view line = lines[i];
        if (line.front() == ' ' || line.front() == '\t') return bad(400, "folded header field");
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos) return bad(400, "header field without ':'");
        const std::string_view name = line.substr(0, colon), value = trim(line.substr(colon + 1));
        if (!is_token(name)) return bad(400, "malformed header field name");  // also "Host :" (RFC 9112 5.1)
        if (!printable(value, true)) return bad(400, "control character in a header field");
        std::string lname(name);
        std::transform(lname.begin(), lname.end(), lname.begin(), lower);
        r.fields.emplace_back(std::move(lname), std::string(value));
    }
    return r;
}

std::string_view reason_phrase(int status) {
    switch (status) {
        case 101:
            return "Switching Protocols";
        case 200:
            return "OK";
        case 400:
            return "Bad Request";
        case 403:
            return "Forbidden";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 426:
            return "Upgrade Required";
        case 431:
            return "Request Header Fields Too Large";
        case 503:
            return "Service Unavailable";
        default:
            return "Error";
    }
}

std::string http_error(int status, std::string_view why) {
    const std::string body = std::string(why) + "\n";
    std::string out = "HTTP/1.1 " + std::to_string(status) + " " + std::string(reason_phrase(status)) + "\r\n";
    if (status == 405) out += "Allow: GET, HEAD\r\n";
    if (status == 426) out += "Sec-WebSocket-Version: 13\r\n";
    out += "Content-Type: text/plain; charset=utf-8\r\nContent-Length: " + std::to_string(body.size()) +
           "\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n" + body;
    return out;
}

}  // namespace arbor::view
