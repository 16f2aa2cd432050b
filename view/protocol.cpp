#include "view/protocol.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <initializer_list>

namespace arbor::view {

namespace {

using nlohmann::json;

/// Largest coordinate a camera may have: far beyond any scene, and still squared safely in float.
constexpr double max_coordinate = 1e18;

struct Bad {
    std::string why;
};

/// The object's keys must all be in `allowed`.
void only_keys(const json& j, std::initializer_list<const char*> allowed) {
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const char* k : allowed) ok |= it.key() == k;
        if (!ok) throw Bad{"unknown field '" + it.key().substr(0, 40) + "'"};
    }
}

engine::Vec3f vec3(const json& j, const char* key) {
    const auto it = j.find(key);
    if (it == j.end()) throw Bad{std::string("missing field '") + key + "'"};
    if (!it->is_array() || it->size() != 3) throw Bad{std::string("'") + key + "' is not an array of 3 numbers"};
    float v[3];
    for (std::size_t i = 0; i < 3; ++i) {
        const json& e = (*it)[i];
        if (!e.is_number()) throw Bad{std::string("'") + key + "' is not an array of 3 numbers"};
        const double d = e.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > max_coordinate) throw Bad{std::string("'") + key + "' is out of range"};
        v[i] = float(d);
    }
    return {v[0], v[1], v[2]};
}

int integer(const json& j, const char* key, int lo, int hi) {
    const json& e = j.at(key);
    if (!e.is_number_integer()) throw Bad{std::string("'") + key + "' is not an integer"};
    const std::int64_t v = e.is_number_unsigned() ? std::int64_t(std::min<std::uint64_t>(e.get<std::uint64_t>(), 1ull << 62))
                                                  : e.get<std::int64_t>();
    if (v < lo || v > hi)
        throw Bad{std::string("'") + key + "' must be in " + std::to_string(lo) + ".." + std::to_string(hi)};
    return int(v);
}

const std::string& text(const json& j, const char* key) {
    const json& e = j.at(key);
    if (!e.is_string()) throw Bad{std::string("'") + key + "' is not a string"};
    return e.get_ref<const std::string&>();
}

CameraMessage camera(const json& j) {
    only_keys(j, {"type", "eye", "look_at", "up", "fov"});
    CameraMessage m;
    engine::Camera& c = m.camera;
    c.eye = vec3(j, "eye");
    c.look_at = vec3(j, "look_at");
    c.up = vec3(j, "up");
    const auto fov = j.find("fov");
    if (fov == j.end() || !fov->is_number()) throw Bad{"'fov' is not a number"};
    const double deg = fov->get<double>();
    if (!(deg >= 1.0 && deg <= 170.0)) throw Bad{"'fov' must be in 1..170 degrees"};
    c.vfov_degrees = float(deg);
    // The basis the camera makes must exist: a view direction, and an up not along it (in double,
    // on the float values the camera will use).
    const double f[3] = {double(c.look_at.x) - c.eye.x, double(c.look_at.y) - c.eye.y, double(c.look_at.z) - c.eye.z};
    const double u[3] = {c.up.x, c.up.y, c.up.z};
    const double ff = f[0] * f[0] + f[1] * f[1] + f[2] * f[2], uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double cx = f[1] * u[2] - f[2] * u[1], cy = f[2] * u[0] - f[0] * u[2], cz = f[0] * u[1] - f[1] * u[0];
    const double scale = max_coordinate * 4.0;  // keeps the squares below double's range
    if (!(ff > 1e-24 * (c.eye.x * c.eye.x + c.eye.y * c.eye.y + c.eye.z * c.eye.z) && ff > 1e-30))
        throw Bad{"'eye' and 'look_at' coincide"};
    if (!(uu > 1e-30)) throw Bad{"'up' is zero"};
    if (!((cx * cx + cy * cy + cz * cz) > 1e-8 * ff * uu) || ff > scale * scale) throw Bad{"'up' is along the view"};
    return m;
}

SettingsMessage settings(const json& j, const Limits& limits) {
    only_keys(j, {"type", "accel", "integrator", "spp", "threads", "width", "height", "cost"});
    SettingsMessage m;
    if (j.contains("accel")) {
        const auto k = accel::parse_accel_kind(text(j, "accel"));
        if (!k || *k == accel::AccelKind::automatic) throw Bad{"unknown structure"};
        m.accel = *k;
    }
    if (j.contains("integrator")) {
        const auto k = engine::parse_integrator(text(j, "integrator"));
        if (!k) throw Bad{"unknown integrator"};
        m.integrator = *k;
    }
    if (j.contains("spp")) m.spp = integer(j, "spp", 1, limits.max_spp);
    if (j.contains("threads")) m.threads = integer(j, "threads", 1, std::max(1, limits.max_threads));
    if (j.contains("width")) m.width = integer(j, "width", Limits::min_size, limits.max_width);
    if (j.contains("height")) m.height = integer(j, "height", Limits::min_size, limits.max_height);
    if (j.contains("cost")) {
        const std::string& q = text(j, "cost");
        if (q == "nodes") m.cost = CostQuantity::nodes;
        else if (q == "tris") m.cost = CostQuantity::tris;
        else throw Bad{"'cost' must be nodes or tris"};
    }
    return m;
}

AckMessage ack(const json& j) {
    only_keys(j, {"type", "frame"});
    const auto f = j.find("frame");
    if (f == j.end() || !f->is_number_unsigned()) throw Bad{"'frame' is not a frame number"};
    return {f->get<std::uint64_t>()};
}

}  // namespace

void SettingsMessage::apply(ViewSettings& s) const {
    if (accel) s.accel = *accel;
    if (integrator) s.integrator = *integrator;
    if (spp) s.spp = *spp;
    if (threads) s.threads = *threads;
    if (width) s.width = *width;
    if (height) s.height = *height;
    if (cost) s.cost = *cost;
}

std::optional<ClientMessage> parse_client_message(std::string_view bytes, const Limits& limits, std::string* error) {
    try {
        if (bytes.size() > max_message_bytes)
            throw Bad{"message of " + std::to_string(bytes.size()) + " bytes (at most " + std::to_string(max_message_bytes) + ")"};
        const json j = json::parse(bytes.begin(), bytes.end(), nullptr, false);
        if (j.is_discarded()) throw Bad{"not JSON"};
        if (!j.is_object()) throw Bad{"not a JSON object"};
        const auto type = j.find("type");
        if (type == j.end() || !type->is_string()) throw Bad{"no 'type'"};
        const std::string& t = type->get_ref<const std::string&>();
        if (t == "camera") return camera(j);
        if (t == "settings") return settings(j, limits);
        if (t == "ack") return ack(j);
        throw Bad{"unknown type"};
    } catch (const Bad& b) {
        if (error) *error = b.why;
    } catch (const std::exception& e) {  // nlohmann's own (e.g. a number too large for its type)
        if (error) *error = std::string("bad message: ") + e.what();
    }
    return std::nullopt;
}

std::string_view to_string(CostQuantity q) { return q == CostQuantity::nodes ? "nodes" : "tris"; }

}  // namespace arbor::view
