#include "view/session.h"

#include "accel/util/timer.h"
#include "engine/plan.h"
#include "engine/renderer.h"
#include "view/frame.h"

#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include <cstring>
#include <memory>

namespace arbor::view {

namespace {

using nlohmann::json;

json vec(const engine::Vec3f& v) { return json::array({v.x, v.y, v.z}); }

constexpr accel::AccelKind choosable[] = {accel::AccelKind::brute, accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah,
                                          accel::AccelKind::lbvh, accel::AccelKind::kdtree};
constexpr engine::IntegratorKind integrators[] = {engine::IntegratorKind::primary, engine::IntegratorKind::ao,
                                                  engine::IntegratorKind::direct, engine::IntegratorKind::path,
                                                  engine::IntegratorKind::cost};

json settings_json(const ViewSettings& s) {
    return {{"accel", accel::to_string(s.accel)}, {"integrator", engine::to_string(s.integrator)}, {"spp", s.spp},
            {"threads", s.threads},         {"width", s.width},   {"height", s.height},
            {"cost", to_string(s.cost)}};
}

/// Whether going from `a` to `b` changes the picture (or its figures: a structure change shows
/// that structure's speed from its first pass).
bool restarts(const ViewSettings& a, const ViewSettings& b) {
    return a.accel != b.accel || a.integrator != b.integrator || a.width != b.width || a.height != b.height ||
           a.cost != b.cost;
}

/// A binary frame: 4-byte little-endian length of the JSON figures, the figures, the JPEG.
std::string frame_message(const std::string& figures, const std::string& jpeg) {
    std::string out(4, '\0');
    const auto n = std::uint32_t(figures.size());
    for (int i = 0; i < 4; ++i) out[std::size_t(i)] = char((n >> (8 * i)) & 0xFF);
    return out + figures + jpeg;
}

}  // namespace

Session::Session(const engine::Scene& scene, const engine::LightSet& lights, StructureCache& cache, const Limits& limits,
                 const ViewSettings& initial, Sink& sink)
    : scene_(scene), lights_(lights), cache_(cache), limits_(limits), sink_(sink), settings_(initial), camera_(scene.camera) {}

Session::~Session() { stop(); }

std::string Session::hello(int client) const {
    const std::lock_guard lock(mutex_);
    json accels = json::array(), integ = json::array();
    for (auto k : choosable) accels.push_back(accel::to_string(k));
    for (auto k : integrators) integ.push_back(engine::to_string(k));
    const accel::Bounds box = engine::scene_bounds(scene_);
    const json j = {{"type", "hello"},
                    {"client", client},
                    {"scene", scene_.name},
                    {"triangles", scene_.placed.empty() ? std::uint64_t(scene_.mesh.triangle_count())
                                                        : scene_.placed.effective_triangles()},
                    {"camera", {{"eye", vec(camera_.eye)}, {"look_at", vec(camera_.look_at)}, {"up", vec(camera_.up)},
                                {"fov", camera_.vfov_degrees}}},
                    {"bounds", {{"lo", vec(box.lo)}, {"hi", vec(box.hi)}}},
                    {"accels", accels},
                    {"integrators", integ},
                    {"settings", settings_json(settings_)},
                    {"limits", {{"max_threads", limits_.max_threads}, {"max_width", limits_.max_width},
                                {"max_height", limits_.max_height}, {"max_spp", limits_.max_spp},
                                {"min_size", Limits::min_size}, {"max_message_bytes", max_message_bytes}}}};
    return j.dump();
}

void Session::start() {
    worker_ = std::thread([this] { run(); });
}

void Session::cancel_refinement_locked() {
    if (running_ && !running_first_) running_->cancel();
}

void Session::handle(const ClientMessage& m) {
    {
        const std::lock_guard lock(mutex_);
        if (const auto* c = std::get_if<CameraMessage>(&m)) {
            camera_ = c->camera;
            ++version_;
            cancel_refinement_locked();
        } else if (const auto* s = std::get_if<SettingsMessage>(&m)) {
            const ViewSettings before = settings_;
            s->apply(settings_);
            if (restarts(before, settings_)) {
                ++version_;
                cancel_refinement_locked();
            }
        } else if (const auto* a = std::get_if<AckMessage>(&m)) {
            if (a->frame == sent_frame_) acked_ = true;
        }
    }
    wake_.notify_all();
}

void Session::stop() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
        if (running_) running_->cancel();
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
}

SessionCounters Session::counters() const {
    const std::lock_guard lock(mutex_);
    return counters_;
}

bool Session::wait_for_work(std::uint64_t acc_version, int samples, ViewSettings& s, engine::Camera& cam,
                            std::uint64_t& version) {
    std::unique_lock lock(mutex_);
    wake_.wait(lock, [&] { return stop_ || version_ != acc_version || samples < settings_.spp; });
    if (stop_) return false;
    s = settings_, cam = camera_, version = version_;
    return true;
}

void Session::run() {
    try {
        loop();
    } catch (const std::exception& e) {  // a failed build (out of memory) or encode: this page stops, others go on
        const json error = {{"type", "error"}, {"message", e.what()}};
        sink_.send_text(error.dump());
    }
}

void Session::loop() {
    Accumulator acc;
    std::uint64_t acc_version = ~std::uint64_t(0);
    std::unique_ptr<tbb::task_arena> arena;
    int arena_threads = 0;
    StructureCache::Entry structure;
    ViewSettings built;  // the accel and integrator `structure` was got for
    accel::Timer since_last;
    for (;;) {
        ViewSettings s;
        engine::Camera cam;
        std::uint64_t version = 0;
        if (!wait_for_work(acc_version, acc.samples(), s, cam, version)) return;
        const bool first = version != acc_version;
        if (first) acc.reset(), acc_version = version;
        if (!arena || arena_threads != s.threads) {
            arena = std::make_unique<tbb::task_arena>(s.threads);
            arena_threads = s.threads;
        }
        const bool counting = s.integrator == engine::IntegratorKind::cost;
        if (!structure.accel || built.accel != s.accel || (built.integrator == engine::IntegratorKind::cost) != counting) {
            structure = {};  // freed first when no other page uses it
            const json note = {{"type", "building"}, {"accel", accel::to_string(s.accel)}};
            if (!sink_.send_text(note.dump())) return;
            arena->execute([&] { structure = cache_.get(s.accel, counting); });
            built = s;
        }

        engine::RenderSettings rs;
        rs.width = s.width, rs.height = s.height, rs.spp = 1, rs.integrator = s.integrator;
        rs.seed = std::uint32_t(acc.samples());  // an independent set of streams per pass
        rs.layers = engine::Layers{};
        const engine::RenderPlan plan = engine::make_plan(scene_, lights_, rs);
        tbb::task_group group;
        {
            const std::lock_guard lock(mutex_);
            if (stop_) return;
            if (!first && version_ != version) continue;
            running_ = &group, running_first_ = first;
        }
        const accel::Timer pass_timer;
        engine::Image pass;
        engine::RenderStats stats;
        tbb::task_group_status status;
        try {
            status = arena->execute([&] {
                return group.run_and_wait(
                    [&] { pass = engine::render(scene_, cam, lights_, plan, *structure.accel, rs, &stats); });
            });
        } catch (...) {
            // A pass that throws (the cost integrator on a structure that cannot count: a scene of
            // instances) ends this page; stop() must not cancel the group that is gone.
            const std::lock_guard lock(mutex_);
            running_ = nullptr;
            throw;
        }
        const double render_ms = pass_timer.ms();
        {
            const std::lock_guard lock(mutex_);
            running_ = nullptr;
            if (status == tbb::task_group_status::canceled) {
                ++counters_.cancelled;
                counters_.cancelled_pass_ms = render_ms;
                continue;
            }
            ++counters_.passes;
        }
        acc.add(pass);

        const accel::Timer encode_timer;
        double cost_top = 0;
        const std::string quantity(to_string(s.cost));
        const std::string jpeg = encode_jpeg(acc.picture(counting ? quantity : std::string(), &cost_top));
        const double encode_ms = encode_timer.ms();
        json mrays = json::object();
        std::uint64_t rays = 0;
        for (std::size_t k = 0; k < engine::render_ray_kind_count; ++k) {
            rays += stats.rays[k];
            const double t = stats.trace_seconds[k] / double(arena_threads);
            if (stats.rays[k] && t > 0) mrays[std::string(engine::to_string(engine::RenderRayKind(k)))] = double(stats.rays[k]) / t * 1e-6;
        }
        json figures = {{"type", "frame"},           {"samples", acc.samples()},    {"target", s.spp},
                        {"width", s.width},          {"height", s.height},          {"accel", accel::to_string(s.accel)},
                        {"integrator", engine::to_string(s.integrator)},            {"threads", arena_threads},
                        {"build_ms", structure.build_ms}, {"build_shared", structure.shared}, {"render_ms", render_ms},
                        {"encode_ms", encode_ms},   {"rays", rays},                {"mrays", mrays},
                        {"mrays_overall", render_ms > 0 ? double(rays) / render_ms * 1e-3 : 0.0}};
        if (counting) figures["cost"] = quantity, figures["cost_top"] = cost_top;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || acked_; });
            if (stop_) return;
            if (!first && version_ != version) continue;  // a refinement of a picture that is gone
            acked_ = false;
            figures["frame"] = ++sent_frame_;
            ++counters_.frames;
        }
        figures["interval_ms"] = since_last.ms();
        since_last = accel::Timer();
        if (!sink_.send_binary(frame_message(figures.dump(), jpeg))) return;
    }
}

}  // namespace arbor::view
