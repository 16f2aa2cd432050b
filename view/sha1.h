#pragma once
/// SHA-1 (FIPS 180-4) and base64 (RFC 4648, with padding): what the WebSocket handshake's
/// Sec-WebSocket-Accept needs (RFC 6455 4.2.2). Not for security: the handshake only shows that the
/// server read the client's key.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace arbor::view {

/// The 20-byte digest of `bytes`.
std::array<std::uint8_t, 20> sha1(std::string_view bytes);
/// `bytes` in base64 (standard alphabet, '=' padding).
std::string base64(std::string_view bytes);

}  // namespace arbor::view
