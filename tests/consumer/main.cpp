// The README's example ("Use arbor from C++"), compiled against the installed package with the
// consumer's own default flags: load a model, build two structures, run the four queries.
#include <arbor/arbor.h>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
    arbor::Scene scene = arbor::Scene::load(argc > 1 ? argv[1] : "bunny.obj");
    float lo[3], hi[3];
    scene.bounds(lo, hi);
    const float c[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    std::vector<arbor::Ray> rays(64);  // a row of rays along x, through the middle of the model
    for (int i = 0; i < 64; ++i)
        rays[i] = {{lo[0] + (hi[0] - lo[0]) * (i + 0.5f) / 64, c[1], hi[2] + 1}, 0, {0, 0, -1}, 1e30f};
    for (const char* structure : {"bvh-sah", "lbvh"}) {
        scene.build({structure});
        std::vector<arbor::Hit> hits = scene.intersect(rays);             // closest hit
        std::vector<bool> blocked = scene.occluded(rays);                 // any hit
        std::vector<arbor::Hit> all(rays.size() * 8);                     // all hits, 8 per ray
        std::vector<std::int32_t> counts(rays.size());
        scene.intersect_all(arbor::RayArrays::of(rays.data(), rays.size()), 8, all.data(), counts.data());
        std::vector<arbor::ClosestPoint> near = scene.closest_point({c[0], c[1], c[2]});
        std::vector<bool> inside = scene.inside({c[0], c[1], c[2]});
        int hit = 0, crossings = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            hit += hits[i].hit();
            crossings += counts[i];
            if (hits[i].hit() != blocked[i] || (hits[i].hit() && all[i * 8].t != hits[i].t)) return 1;
        }
        std::printf("%s: %d of %zu rays hit, %d crossings; nearest surface point to the centre %.4g away "
                    "(mesh %u, triangle %u), centre %s\n",
                    scene.accel().c_str(), hit, rays.size(), crossings, near[0].distance, near[0].geom, near[0].prim,
                    inside[0] ? "inside" : "outside");
        if (hit == 0 || !near[0].found()) return 1;
    }
    return 0;
}
