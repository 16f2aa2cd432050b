// Builds a sphere, traces one ray with brute force, exits 0 only on the expected hit.
#include <accel/accel.h>
#include <engine/procedural.h>

#include <cmath>
#include <cstdio>

int main() {
    using namespace arbor;
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
    const auto accel = accel::make_accel(accel::AccelKind::brute, sphere.view());
    const accel::Ray ray{{0, 0, 5}, 0.0f, {0, 0, -1}, INFINITY};
    accel::Hit hit;
    accel->trace({&ray, 1}, {&hit, 1}, {accel::Query::closest, accel::TracePath::best});
    std::printf("t = %g, prim = %u\n", hit.t, hit.prim);
    return hit.is_hit() && std::fabs(hit.t - 4.0f) < 0.05f ? 0 : 1;
}
