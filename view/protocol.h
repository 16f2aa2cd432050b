#pragma once
/// What the viewer's page and server say to each other over the WebSocket (`arbor view`).
///
/// Page -> server: JSON text messages of at most max_message_bytes, each an object with a "type":
///   {"type":"camera","eye":[x,y,z],"look_at":[x,y,z],"up":[x,y,z],"fov":deg}
///   {"type":"settings","accel":NAME,"integrator":NAME,"spp":N,"threads":N,"width":W,"height":H,
///    "cost":"nodes"|"tris"}          (every field but "type" optional)
///   {"type":"ack","frame":N}        (the page has shown frame N: the server sends one frame at a time)
/// Anything else (not JSON, another type, an unknown or missing field, a value of the wrong type or
/// outside its range, a degenerate camera) is a bad message: the server closes that connection.
/// The parser is the only code that reads the page's bytes, and it is fuzzed (fuzz/).
///
/// Server -> page: a text "hello" (scene, camera, choices, limits) when the socket opens, a text
/// "building" before a structure is built, and binary frames: a 4-byte little-endian length, that
/// many bytes of JSON figures (frame, samples, ms, Mrays/s per ray kind, ...) and a JPEG image.
#include "accel/interface/accel.h"
#include "engine/camera.h"
#include "engine/render_settings.h"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace arbor::view {

/// Longest message the page may send; a longer one closes its connection.
inline constexpr std::size_t max_message_bytes = 4096;

/// What a page may ask for.
struct Limits {
    int max_threads = 1;  ///< the server's --threads (or the machine's cores)
    int max_width = 1920, max_height = 1200, max_spp = 4096;
    static constexpr int min_size = 16;
};

/// Which quantity the cost integrator shows.
enum class CostQuantity { nodes, tris };

/// The render a page asks for; every field has its value (defaults, then the page's changes).
struct ViewSettings {
    accel::AccelKind accel = accel::AccelKind::bvh_sah;
    engine::IntegratorKind integrator = engine::IntegratorKind::direct;
    int spp = 64;  ///< samples per pixel to accumulate while the camera is still
    int threads = 1;
    int width = 640, height = 480;
    CostQuantity cost = CostQuantity::nodes;
};

struct CameraMessage {
    engine::Camera camera;
};
/// A settings message: only the fields it holds change.
struct SettingsMessage {
    std::optional<accel::AccelKind> accel;
    std::optional<engine::IntegratorKind> integrator;
    std::optional<int> spp, threads, width, height;
    std::optional<CostQuantity> cost;

    void apply(ViewSettings& s) const;
};
struct AckMessage {
    std::uint64_t frame = 0;
};
using ClientMessage = std::variant<CameraMessage, SettingsMessage, AckMessage>;

/// Parses one message from the page; nullopt (and `error`, when given, says why in one line) for a
/// bad one. Never throws.
std::optional<ClientMessage> parse_client_message(std::string_view text, const Limits& limits,
                                                  std::string* error = nullptr);

/// The names a page may choose from (structures: every kind but auto; integrators: all).
std::string_view to_string(CostQuantity q);

}  // namespace arbor::view
