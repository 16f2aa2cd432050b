#pragma once
/// HTTP/1.x as `arbor view` speaks it (RFC 9112): the head of a request (request line and header
/// fields; the server reads no body) and the answers it writes. One request per connection: every
/// answer says `Connection: close`.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace arbor::view {

/// Longest request head read (request line and header fields); a longer one is answered 431.
inline constexpr std::size_t max_head_bytes = 8192;
/// Most header fields in a head; more is answered 431.
inline constexpr std::size_t max_header_fields = 64;

struct HttpRequest {
    std::string method;                                       ///< as sent ("GET"); methods are case-sensitive
    std::string target;                                       ///< as sent ("/", "/ws?x=1")
    std::string version;                                      ///< "HTTP/1.0" or "HTTP/1.1"
    std::vector<std::pair<std::string, std::string>> fields;  ///< names lower-cased, values trimmed

    /// The value of the first field `lower_name`, nullptr when absent.
    const std::string* field(std::string_view lower_name) const;
    /// How many fields are named `lower_name`.
    std::size_t count(std::string_view lower_name) const;
    /// Whether field `lower_name` holds `token` in its comma-separated list (case-insensitive), as
    /// "Connection: keep-alive, Upgrade" holds "upgrade".
    bool has_token(std::string_view lower_name, std::string_view token) const;
    /// The target up to its query ('?').
    std::string_view path() const;
};

/// The length of the head at the start of `bytes` up to and including its blank line (CRLF CRLF,
/// or bare LFs), or 0 while the blank line has not arrived.
std::size_t head_length(std::string_view bytes);

/// Parses a complete head (what head_length measured); nullopt for a malformed one, with the
/// status to answer (400, or 431 for too many fields) and a one-line reason.
std::optional<HttpRequest> parse_request_head(std::string_view head, int* status, std::string* why);

/// A whole answer with a text/plain body (`why` and a newline) and `Connection: close`.
std::string http_error(int status, std::string_view why);
/// The reason phrase of the statuses the viewer answers ("Not Found"); "Error" for others.
std::string_view reason_phrase(int status);

}  // namespace arbor::view
