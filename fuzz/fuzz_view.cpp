#include <cmath>
#include <string>
#include <string_view>

#include "fuzz/fuzz_targets.h"
#include "view/http.h"
#include "view/protocol.h"
#include "view/websocket.h"

namespace arbor::fuzz {

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw FuzzFinding("view message: " + what);
}

bool finite(const engine::Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The same bytes as a request head and as the page's WebSocket frames: the other two parsers of
/// network bytes. Refusals carry a reason and a status or close code; the frame reader never waits
/// for more input with a full buffer (the connection would stall).
void fuzz_wire(std::string_view bytes) {
    const std::size_t head = view::head_length(bytes);
    int status = 0;
    std::string why;
    if (!view::parse_request_head(bytes.substr(0, head ? head : bytes.size()), &status, &why))
        require(!why.empty() && (status == 400 || status == 431), "request head refused without a reason or status");
    view::ws::MessageReader reader(view::max_message_bytes);
    std::string buf(bytes);
    for (;;) {
        const view::ws::Event e = reader.next(buf);
        if (e.kind == view::ws::Event::need_more) {
            require(buf.size() < reader.buffer_bytes(), "the frame reader waits for more with a full buffer");
            return;
        }
        if (e.kind == view::ws::Event::error) {
            require(!e.why.empty() && (e.code == view::ws::protocol_error || e.code == view::ws::too_big),
                    "frame refused without a reason or with another code");
            return;
        }
        if (e.kind == view::ws::Event::message)
            require(e.payload.size() <= view::max_message_bytes, "a message over the limit");
    }
}

}  // namespace

void fuzz_view_message(const std::uint8_t* data, std::size_t size) {
    view::Limits limits;
    limits.max_threads = 4;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    fuzz_wire(text);
    std::string why;
    const auto m = view::parse_client_message(text, limits, &why);
    if (!m) {
        require(!why.empty(), "refused without a reason");
        return;
    }
    require(size <= view::max_message_bytes, "a message longer than the limit parsed");
    if (const auto* c = std::get_if<view::CameraMessage>(&*m)) {
        const engine::Camera& cam = c->camera;
        require(finite(cam.eye) && finite(cam.look_at) && finite(cam.up), "a camera with a non-finite vector");
        require(cam.vfov_degrees >= 1.0f && cam.vfov_degrees <= 170.0f, "a field of view out of range");
        // The camera must make a finite basis, as the renderer will compute it.
        engine::Camera prepared = cam;
        prepared.prepare(64, 48);
        const accel::Ray r = prepared.ray(32.0f, 24.0f);
        require(finite(r.dir) && (r.dir.x != 0.0f || r.dir.y != 0.0f || r.dir.z != 0.0f), "a camera without a view direction");
    } else if (const auto* s = std::get_if<view::SettingsMessage>(&*m)) {
        view::ViewSettings v;
        s->apply(v);
        require(v.spp >= 1 && v.spp <= limits.max_spp, "spp out of range");
        require(v.threads >= 1 && v.threads <= limits.max_threads, "threads out of range");
        require(v.width >= view::Limits::min_size && v.width <= limits.max_width, "width out of range");
        require(v.height >= view::Limits::min_size && v.height <= limits.max_height, "height out of range");
        require(v.accel != accel::AccelKind::automatic, "auto offered");
    }
}

}  // namespace arbor::fuzz
