#include "engine/render_job.h"

#include <algorithm>

namespace arbor::engine {

RenderRays render_rays(const Scene& scene, const RenderPlan& plan, const RenderSettings& set, double renders) {
    RenderRays out;
    const double samples = double(set.width) * double(set.height) * double(plan.spp) * renders;
    // A sample of the camera rays in the renderer's order: whole 16x16 tiles spread over the image,
    // 16 of them (4096 rays), each tile's rays row by row.
    Camera cam = scene.camera;
    cam.prepare(set.width, set.height);
    const int tile = 16;
    const int tiles_x = std::max(1, set.width / tile), tiles_y = std::max(1, set.height / tile);
    const int want = std::min(16, tiles_x * tiles_y);
    for (int k = 0; k < want; ++k) {
        const int t = int((long(k) * tiles_x * tiles_y) / want);
        const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        for (int y = y0; y < std::min(y0 + tile, set.height); ++y)
            for (int x = x0; x < std::min(x0 + tile, set.width); ++x) out.camera_sample.push_back(cam.ray(float(x) + 0.5f, float(y) + 0.5f));
    }
    auto group = [&](const char* name, double per_sample, accel::Query q, accel::RayHint hint) {
        if (per_sample <= 0.0) return;
        accel::RayGroup g;
        g.name = name;
        g.shape.rays = samples * per_sample;
        g.shape.query = q;
        g.shape.hint = hint;
        out.groups.push_back(g);
    };
    group("camera", 1.0, accel::Query::closest, accel::RayHint::coherent);
    out.groups.front().sample = out.camera_sample;
    const int depth = std::max(plan.depth, 0);
    const double bounces = plan.diffuse ? double(std::min(depth, set.rr_depth + 1)) : 0.0;
    const double mirrors = plan.mirror ? 1.0 : 0.0;
    const double vertices = 1.0 + bounces + mirrors;
    const double per_vertex = (plan.point_shadows ? double(scene.lights.size()) : 0.0) + (plan.area_shadows ? 1.0 : 0.0);
    group("shadow", per_vertex * vertices, accel::Query::any, accel::RayHint::coherent);
    group("bounce", bounces + mirrors, accel::Query::closest, accel::RayHint::incoherent);
    group("ao", plan.ao ? double(plan.ao_samples) : 0.0, accel::Query::any, accel::RayHint::incoherent);
    return out;
}

accel::AutoJob render_job(const Scene& scene, const RenderRays& rays, const accel::BuildConfig& build) {
    accel::AutoJob job;
    job.tris = scene.mesh.view();
    job.groups = rays.groups;
    job.build = build;
    return job;
}

}  // namespace arbor::engine
