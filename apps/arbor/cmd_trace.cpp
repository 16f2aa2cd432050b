/// `arbor trace --scene MODEL.obj|builtin:NAME --rays RAYS.rays [--hits OUT.hits] [--accel NAME] [--occluded]
///  [--leaf-size N] [--sah-bins N] [--threads N] [--repeat K] [--path P] [--json]` (spec/cli.md).
#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"
#include "accel/interface/trace.h"
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "engine/builtin_scenes.h"
#include "engine/log.h"
#include "engine/mesh_loader.h"
#include "engine/rayfile.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace arbor::app {

namespace {

struct TraceOptions {
    std::string scene, rays, hits, accel = "bvh-sah", path = "best";
    accel::BuildConfig build;
    bool occluded = false, json = false;
    int threads = 0, repeat = 1;
};

int run_trace(const TraceOptions& o) {
    const auto limit = limit_threads(o.threads);
    engine::Warnings warnings;
    const engine::Mesh mesh = engine::is_builtin_scene(o.scene) ? engine::make_builtin_scene(o.scene).mesh
                                                                : engine::load_mesh(o.scene, warnings, o.build.max_memory);
    const std::vector<accel::Ray> rays = engine::read_rays(o.rays, o.build.max_memory);
    // Only the layout the path reads is built (the path policy says which).
    const auto asked = *accel::parse_trace_path(o.path);
    const auto query = o.occluded ? accel::Query::any : accel::Query::closest;
    accel::BuildConfig build = o.build;
    build.layouts = accel::layouts_for(asked);
    // The job auto decides for: these rays, traced --repeat times, on the path asked (best: auto's).
    accel::AccelPick pick =
        resolve_accel(o.accel, accel::trace_job(mesh.view(), rays, double(rays.size()) * double(o.repeat), query, asked, build));

    // With auto, its probe may have built the pick already: then its own build time counts.
    const bool was_prebuilt = pick.built != nullptr;
    const accel::Timer build_timer;
    const auto structure = was_prebuilt ? std::move(pick.built) : accel::make_accel(pick.kind, mesh.view(), build);
    const double build_ms = was_prebuilt ? structure->stats().build_ms : build_timer.ms();

    // The one path decision, for the whole file: what was asked, else auto's calibrated path, else
    // what the structure has and the rays' coherence say (accel/interface/path_policy.h).
    // A batch the policy's measure cannot call (diffuse rays: accel/interface/path_race.h) is raced
    // on the first pass; the other passes take the winner.
    const accel::TraceRequest asked_req{query, asked, accel::RayHint::unknown, pick.path};
    const accel::PathChoice choice = accel::choose_path(structure->offer(), rays, asked_req);
    accel::TracePath path = choice.path;
    std::string path_reason = accel::path_reason(choice);
    const bool race = accel::race_settles(choice, structure->offer(), asked_req) &&
                      accel::race_chunk_count((rays.size() + 1023) / 1024) != 0;
    accel::RaceOutcome raced;
    const accel::AccelKind kind = pick.kind;

    std::vector<accel::Hit> hits(rays.size());
    std::vector<double> times;
    for (int k = 0; k < o.repeat; ++k) {
        const accel::Timer t;
        if (k == 0 && race) {
            raced = accel::trace_parallel(*structure, rays, hits, query, accel::TracePath::best);
            if (raced.raced()) path = raced.path, path_reason += "; " + accel::race_reason(raced);
        } else {
            accel::trace_parallel(*structure, rays, hits, query, path);
        }
        times.push_back(t.ms());
    }
    std::sort(times.begin(), times.end());
    const double median_ms = times[times.size() / 2];
    const auto nhit = std::size_t(std::count_if(hits.begin(), hits.end(), [](const accel::Hit& h) { return h.is_hit(); }));
    if (!o.hits.empty()) engine::write_hits(o.hits, hits);

    nlohmann::json j;
    j["accel"] = accel::to_string(kind);
    if (accel::parse_accel_kind(o.accel) == accel::AccelKind::automatic) {
        j["auto_reason"] = pick.reason;
        j["auto_ms"] = pick.auto_ms;
        j["auto_own_ms"] = pick.own_ms;
        j["auto_probed"] = pick.probed;
    }
    j["path"] = accel::to_string(path);
    j["path_reason"] = path_reason;
    if (raced.raced())
        j["path_race"] = {{"chunks", raced.chunks},
                          {"single_ns_per_ray", raced.single_ns},
                          {"packet_ns_per_ray", raced.packet_ns},
                          {"winner", accel::to_string(raced.path)}};
    j["query"] = o.occluded ? "any" : "closest";
    j["triangles"] = mesh.triangle_count();
    j["rays"] = rays.size();
    j["hits"] = nhit;
    j["build_ms"] = build_ms;
    j["trace_ms"] = median_ms;
    j["trace_ms_min"] = times.front();
    j["trace_ms_max"] = times.back();
    j["repeat"] = o.repeat;
    j["mrays_per_s"] = median_ms > 0 ? double(rays.size()) / (median_ms * 1e3) : 0.0;
    j["threads"] = active_threads();
    j["leaf_size"] = o.build.bvh.max_leaf_size;
    const bool has_layouts = kind != accel::AccelKind::brute;
    const std::string& fallback = structure->stats().compact_fallback;  // compact mode, since the default did not fit
    const bool compact = !fallback.empty() || (build.compact && (kind == accel::AccelKind::bvh_median ||
                                                                 kind == accel::AccelKind::bvh_sah || kind == accel::AccelKind::lbvh));
    j["layouts"] = has_layouts ? (compact                                   ? "compact"
                                  : build.layouts == accel::Layouts::scalar ? "scalar"
                                                                            : "simd")
                               : "none";
    std::vector<std::string> skipped;
    if (!fallback.empty()) {
        accel::BuildConfig as_built = build;
        as_built.compact = true;
        skipped = accel::skipped_by_build(kind, as_built);
        skipped.insert(skipped.begin(), "the default SIMD layout, for compact mode (" + fallback + ")");
        j["compact_fallback"] = fallback;
    } else {
        skipped = accel::skipped_by_build(kind, build);
    }
    j["skipped"] = skipped;
    put_stats(j, structure->stats());
    if (o.json) {
        std::cout << j.dump() << '\n';
        return 0;
    }
    engine::print_warnings(warnings);
    std::printf("%s: %zu triangles, %zu rays, %zu hits; build %.2f ms, trace %.2f ms (median of %d), "
                "%.3g Mrays/s, %d thread%s, path %s (%s)%s%s\n",
                std::string(j["accel"]).c_str(), mesh.triangle_count(), rays.size(), nhit, build_ms, median_ms,
                o.repeat, double(j["mrays_per_s"]), int(j["threads"]), int(j["threads"]) == 1 ? "" : "s",
                std::string(accel::to_string(path)).c_str(), path_reason.c_str(), skipped.empty() ? "" : "; skipped: ",
                skipped.empty() ? "" : skipped[0].c_str());
    for (std::size_t i = 1; i < skipped.size(); ++i) std::printf("also skipped: %s\n", skipped[i].c_str());
    return 0;
}

}  // namespace

Run add_trace(CLI::App& cmd) {
    auto o = std::make_shared<TraceOptions>();
    cmd.add_option("--scene", o->scene, "mesh file (OBJ, PLY, STL or glTF 2.0) or builtin:NAME")->required();
    cmd.add_option("--rays", o->rays, ".rays file (spec/rayfile.md)")->required();
    cmd.add_option("--hits", o->hits, "write the answers to this .hits file");
    add_accel_option(cmd, o->accel)->capture_default_str();
    add_build_options(cmd, o->build);
    cmd.add_flag("--occluded", o->occluded, "any-hit (shadow) queries");
    add_threads_option(cmd, o->threads);
    cmd.add_option("--repeat", o->repeat, "trace K times, report the median")->check(CLI::Range(1, 100000));
    cmd.add_option("--path", o->path, "traversal path: best, scalar, packet, single")
        ->check([](const std::string& v) -> std::string {
            return accel::parse_trace_path(v) ? std::string() : "unknown path '" + v + "' (expected best, scalar, packet or single)";
        });
    cmd.add_flag("--json", o->json, "one JSON object on standard output");
    return [o] { return run_trace(*o); };
}

}  // namespace arbor::app
