// The viewer's message parser (view/protocol.h): what the page sends parses to exactly those
// values; everything else is refused with a reason and never throws: too long, not JSON, not an
// object, unknown type or field, wrong types, values out of range, degenerate cameras.
#include "view/protocol.h"

#include <doctest/doctest.h>

#include <random>

using namespace arbor;
using view::parse_client_message;

namespace {

view::Limits limits() {
    view::Limits l;
    l.max_threads = 4;
    return l;
}

std::string refusal(const std::string& text) {
    std::string why;
    const auto m = parse_client_message(text, limits(), &why);
    CHECK_MESSAGE(!m, text);
    CHECK(!why.empty());
    return why;
}

}  // namespace

TEST_CASE("view protocol: camera, settings and ack parse to their values") {
    const auto cam = parse_client_message(R"({"type":"camera","eye":[1,2,3.5],"look_at":[0,0,0],"up":[0,1,0],"fov":35})", limits());
    REQUIRE(cam);
    const auto& c = std::get<view::CameraMessage>(*cam).camera;
    CHECK(c.eye.x == 1.0f);
    CHECK(c.eye.z == 3.5f);
    CHECK(c.up.y == 1.0f);
    CHECK(c.vfov_degrees == 35.0f);

    const auto set = parse_client_message(R"({"type":"settings","accel":"kdtree","integrator":"cost","spp":8,"threads":4,
        "width":320,"height":240,"cost":"tris"})", limits());
    REQUIRE(set);
    view::ViewSettings s;
    std::get<view::SettingsMessage>(*set).apply(s);
    CHECK(s.accel == accel::AccelKind::kdtree);
    CHECK(s.integrator == engine::IntegratorKind::cost);
    CHECK(s.spp == 8);
    CHECK(s.threads == 4);
    CHECK(s.width == 320);
    CHECK(s.height == 240);
    CHECK(s.cost == view::CostQuantity::tris);

    // A partial settings message changes only its fields.
    const auto part = parse_client_message(R"({"type":"settings","spp":2})", limits());
    REQUIRE(part);
    std::get<view::SettingsMessage>(*part).apply(s);
    CHECK(s.spp == 2);
    CHECK(s.accel == accel::AccelKind::kdtree);

    const auto ack = parse_client_message(R"({"type":"ack","frame":12345678901})", limits());
    REQUIRE(ack);
    CHECK(std::get<view::AckMessage>(*ack).frame == 12345678901ull);
}

TEST_CASE("view protocol: malformed, unknown and out-of-range messages are refused") {
    CHECK(refusal(std::string(view::max_message_bytes + 1, ' ')).find("bytes") != std::string::npos);
    CHECK(refusal(R"({"type":"ack","frame":1})" + std::string(view::max_message_bytes, ' ')).find("bytes") != std::string::npos);
    CHECK(refusal("") == "not JSON");
    CHECK(refusal("hello") == "not JSON");
    CHECK(refusal(R"({"type":"ack","frame":1)") == "not JSON");
    CHECK(refusal("[1,2,3]") == "not a JSON object");
    CHECK(refusal(R"({"frame":1})") == "no 'type'");
    CHECK(refusal(R"({"type":7})") == "no 'type'");
    CHECK(refusal(R"({"type":"open","path":"/etc/passwd"})") == "unknown type");
    CHECK(refusal(R"({"type":"settings","scene":"/etc/passwd"})").find("unknown field") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","accel":"auto"})") == "unknown structure");
    CHECK(refusal(R"({"type":"settings","accel":"octree"})") == "unknown structure");
    CHECK(refusal(R"({"type":"settings","accel":3})").find("not a string") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","integrator":"magic"})") == "unknown integrator");
    CHECK(refusal(R"({"type":"settings","spp":0})").find("1..4096") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","spp":2.5})").find("not an integer") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","spp":"8"})").find("not an integer") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","threads":5})").find("1..4") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","width":100000})").find("16..1920") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","height":-1})").find("16..1200") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","width":18446744073709551615})").find("16..1920") != std::string::npos);
    CHECK(refusal(R"({"type":"settings","cost":"rays"})").find("nodes or tris") != std::string::npos);
    CHECK(refusal(R"({"type":"ack","frame":-1})").find("frame") != std::string::npos);
    CHECK(refusal(R"({"type":"ack"})").find("frame") != std::string::npos);
    CHECK(refusal(std::string(1000, '[') + std::string(1000, ']')) == "not a JSON object");
}

TEST_CASE("view protocol: cameras must make a view") {
    auto cam = [](const std::string& eye, const std::string& look, const std::string& up, const std::string& fov) {
        return R"({"type":"camera","eye":)" + eye + R"(,"look_at":)" + look + R"(,"up":)" + up + R"(,"fov":)" + fov + "}";
    };
    CHECK(parse_client_message(cam("[0,0,5]", "[0,0,0]", "[0,1,0]", "40"), limits()));
    CHECK(refusal(cam("[1,1,1]", "[1,1,1]", "[0,1,0]", "40")).find("coincide") != std::string::npos);
    CHECK(refusal(cam("[0,5,0]", "[0,0,0]", "[0,1,0]", "40")).find("along the view") != std::string::npos);
    CHECK(refusal(cam("[0,0,5]", "[0,0,0]", "[0,0,0]", "40")).find("zero") != std::string::npos);
    CHECK(refusal(cam("[0,0,5]", "[0,0,0]", "[0,1,0]", "0")).find("fov") != std::string::npos);
    CHECK(refusal(cam("[0,0,5]", "[0,0,0]", "[0,1,0]", "180")).find("fov") != std::string::npos);
    CHECK(refusal(cam("[0,0,5]", "[0,0,0]", "[0,1,0]", "\"40\"")).find("fov") != std::string::npos);
    CHECK(refusal(cam("[0,0,1e999]", "[0,0,0]", "[0,1,0]", "40")) == "not JSON");  // nlohmann refuses overflow
    CHECK(refusal(cam("[0,0,1e30]", "[0,0,0]", "[0,1,0]", "40")).find("out of range") != std::string::npos);
    CHECK(refusal(cam("[0,0]", "[0,0,0]", "[0,1,0]", "40")).find("3 numbers") != std::string::npos);
    CHECK(refusal(cam("[0,0,\"5\"]", "[0,0,0]", "[0,1,0]", "40")).find("3 numbers") != std::string::npos);
    CHECK(refusal(R"({"type":"camera","eye":[0,0,5],"up":[0,1,0],"fov":40})").find("look_at") != std::string::npos);
    CHECK(refusal(R"({"type":"camera","eye":[0,0,5],"look_at":[0,0,0],"up":[0,1,0],"fov":40,"near":1})").find("unknown field") != std::string::npos);
}

TEST_CASE("view protocol: random and mutated bytes never throw") {
    std::mt19937 rng(7);
    const std::string seed = R"({"type":"camera","eye":[1,2,3],"look_at":[0,0,0],"up":[0,1,0],"fov":40})";
    std::size_t parsed = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string s = seed;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) s[rng() % s.size()] = char(rng() % 256);
        if (i % 4 == 0) s.resize(rng() % (s.size() + 1));
        std::string why;
        const auto m = parse_client_message(s, limits(), &why);
        parsed += m.has_value();
        CHECK((m.has_value() || !why.empty()));
    }
    CHECK(parsed > 0);  // some mutations keep a valid camera (a digit for a digit)
}
