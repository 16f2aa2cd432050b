// kd_empty_runs: how a closest-hit rope walk spends its steps in empty leaves (issue 20 item 4,
// perf/results/kdtree-skip-2026-12-03d.md). Per ray file: leaves entered, empty leaves, the runs
// of consecutive empty leaves (lengths 1, 2, 3, >= 4) and the descent steps (interior nodes
// passed) of the rope steps into and out of each run class. Scalar path (kd::walk_ropes with
// counters), one thread.
//
// With --time R: an upper bound on what skipping runs of empty leaves can save, measured. The
// walk's loop (walk_pass's, written out here) is timed against an "oracle" copy that, in the first
// leaf of a run of >= 2 empty leaves, jumps to the state (leaf, t) recorded for the run's last leaf
// in a first pass, i.e. a free skip that costs one rope step per run. Thread CPU time, median of R
// interleaved passes each; both walks use the scalar triangle test, so the saving is reported in ns
// per ray, to be set against the single path's time per ray.
#include "accel/core/hit_record.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "engine/builtin_scenes.h"
#include "engine/obj_loader.h"
#include "engine/rayfile.h"
#include "simd/ray_triangle.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

using namespace arbor;
namespace kd = arbor::accel::kd;

namespace {

double thread_ns() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e9 + double(ts.tv_nsec);
}

/// A leaf entered by the walk's loop: the state after the rope step into it.
/// The scalar path's leaf test (KdTreeAccel::trace_one, closest hit): every reference of `leaf`,
/// the hits offered to `best`, `tfar` lowered to each accepted one.
void test_leaf(const accel::KdTree& tree, const accel::KdLeaf& leaf, const accel::Ray& ray, const simd::WoopShear& shear,
               float& tfar, accel::HitRecord<false>& best) {
    for (std::uint32_t i = leaf.first, end = leaf.first + leaf.count; i < end; ++i) {
        const accel::KdTriangle& tri = tree.tris[tree.refs[i]];
        const simd::TriHit<float> h = simd::woop_test(ray.org, shear, ray.tnear, tfar, tri.v0, tri.v1, tri.v2);
        if (!h.hit || !best.offer(h.t, tri.prim, h.u, h.v)) continue;
        tfar = h.t;
    }
}

struct State {
    std::uint32_t node;
    bool empty;
    double t;
};

/// Closest hit of `ray`: walk_ropes's loop written out; `rec` (when not null) gets the loop's leaf
/// states; `oracle` (when not null) holds them from a first pass, and the first leaf of a run of
/// >= 2 empty leaves jumps to the run's last leaf: to its recorded node (`locate` false: a jump as
/// cheap as a rope step), or to the leaf found by a descent from the root at the recorded t (`locate`
/// true: the cost of locating the landing point without ropes).
accel::Hit trace(const accel::KdTree& tree, const accel::Ray& ray, std::vector<State>* rec, const State* oracle,
                 std::size_t oracle_n, bool locate = false) {
    accel::HitRecord<false> best;
    if (!accel::ray_is_traceable(ray)) return best.hit;
    const simd::WoopShear shear = simd::woop_shear(ray.dir);
    float tfar = ray.tfar;
    auto leaf_fn = [&](std::uint32_t li) {
        test_leaf(tree, tree.leaves[li], ray, shear, tfar, best);
        return false;
    };
    kd::RopeRay s;
    double t0 = 0.0;
    std::uint64_t visited = 0;
    const kd::RopeStart start = kd::rope_start(tree, ray, s, t0);
    if (start != kd::RopeStart::walk) {
        kd::walk_ropes_from<false>(tree, s, t0, start, best.hit.t, leaf_fn, visited);
        return best.hit;
    }
    double t = t0;
    std::uint32_t node = 0;
    unsigned touched = 0;
    kd::RopeStep st = kd::rope_first<false>(tree, s, t0, node, leaf_fn, visited);
    std::size_t j = 0;
    while (st == kd::RopeStep::leaf) {
        const std::uint32_t li = tree.nodes[node].index();
        if (rec) rec->push_back({node, tree.leaves[li].count == 0, t});
        leaf_fn(li);
        if (oracle && j + 1 < oracle_n && oracle[j].empty && oracle[j + 1].empty) {
            std::size_t k = j + 1;
            while (k + 1 < oracle_n && oracle[k + 1].empty) ++k;
            t = oracle[k].t;
            if (locate) {
                bool near = false;
                node = kd::descend(tree.nodes.data(), s, 0, t, kd::point_window(s, t), near, visited);
            } else {
                node = oracle[k].node;
            }
            j = k;
        }
        st = kd::rope_next<false, false>(tree, s, t, node, best.hit.t, leaf_fn, touched, visited);
        ++j;
    }
    if (st != kd::RopeStep::stop && touched != 0) kd::walk_other_sides<false, false>(tree, s, t0, best.hit.t, leaf_fn, visited);
    return best.hit;
}

void time_oracle(const accel::KdTree& tree, const std::vector<accel::Ray>& rays, int repeats) {
    std::vector<State> states;
    std::vector<std::size_t> first(rays.size() + 1, 0);
    std::vector<accel::Hit> base(rays.size()), skip(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        first[i] = states.size();
        base[i] = trace(tree, rays[i], &states, nullptr, 0);
    }
    first[rays.size()] = states.size();
    std::vector<accel::Hit> skip_locate(rays.size());
    std::vector<double> tb, to, tl;
    // walk, skip, skip + locate in rotating order
    for (int r = 0; r < repeats; ++r) {
        for (int pass = 0; pass < 3; ++pass) {
            const int mode = (pass + r) % 3;
            std::vector<accel::Hit>& out = mode == 0 ? base : mode == 1 ? skip : skip_locate;
            const double t_start = thread_ns();
            for (std::size_t i = 0; i < rays.size(); ++i)
                out[i] = trace(tree, rays[i], nullptr, mode ? states.data() + first[i] : nullptr, mode ? first[i + 1] - first[i] : 0,
                               mode == 2);
            (mode == 0 ? tb : mode == 1 ? to : tl).push_back((thread_ns() - t_start) / double(rays.size()));
        }
    }
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
        differ += !accel::hits_agree(base[i], skip[i]) + !accel::hits_agree(base[i], skip_locate[i]);
    std::sort(tb.begin(), tb.end());
    std::sort(to.begin(), to.end());
    std::sort(tl.begin(), tl.end());
    const double mb = tb[tb.size() / 2], mo = to[to.size() / 2], ml = tl[tl.size() / 2];
    std::printf("  timed (scalar triangle test, thread CPU, median of %d): walk %.1f ns/ray; oracle skip %.1f (saved %.1f, "
                "%.1f%%); skip + locate from the root %.1f (saved %.1f, %.1f%%); %zu hits differ\n",
                repeats, mb, mo, mb - mo, 100.0 * (mb - mo) / mb, ml, mb - ml, 100.0 * (mb - ml) / mb, differ);
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 0, first_file = 2;
    if (argc >= 4 && std::string(argv[2]) == "--time") repeats = std::atoi(argv[3]), first_file = 4;
    if (argc <= first_file) {
        std::fprintf(stderr, "usage: kd_empty_runs SCENE(builtin:NAME or .obj) [--time REPEATS] FILE.rays...\n");
        return 2;
    }
    const std::string scene = argv[1];
    engine::Warnings w;
    const engine::Mesh mesh = engine::is_builtin_scene(scene) ? engine::make_builtin_scene(scene).mesh : engine::load_obj(scene, w);
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::scalar;
    const auto built = accel::make_kdtree_accel(mesh.view(), cfg);
    const accel::KdTree& tree = built->tree();
    std::size_t empty_leaves = 0;
    for (const auto& l : tree.leaves) empty_leaves += l.count == 0;
    std::printf("%s: %zu leaves, %zu empty (%.1f%%)\n", scene.c_str(), tree.leaves.size(), empty_leaves,
                100.0 * double(empty_leaves) / double(tree.leaves.size()));
    for (int f = first_file; f < argc; ++f) {
        const std::vector<accel::Ray> rays = engine::read_rays(argv[f]);
        // per run class c (0: non-empty leaf, 1..3: empty run of that length, 4: >= 4): number of
        // runs, leaves in them, descent steps into those leaves
        double runs[5] = {}, leaves[5] = {}, steps[5] = {}, step_after_run[5] = {};
        double total_leaves = 0, total_steps = 0, first_steps = 0;
        struct Entry {
            bool empty;
            std::uint64_t steps;
        };
        std::vector<Entry> seq;
        for (const accel::Ray& ray : rays) {
            accel::HitRecord<false> best;
            if (!accel::ray_is_traceable(ray)) continue;
            const simd::WoopShear shear = simd::woop_shear(ray.dir);
            float tfar = ray.tfar;
            std::uint64_t visited = 0, last = 0;
            seq.clear();
            auto leaf_fn = [&](std::uint32_t li) {
                const accel::KdLeaf& leaf = tree.leaves[li];
                seq.push_back({leaf.count == 0, visited - last});
                last = visited;
                test_leaf(tree, leaf, ray, shear, tfar, best);
                return false;
            };
            accel::kd::walk_ropes<false, true>(tree, ray, best.hit.t, leaf_fn, visited);
            total_leaves += double(seq.size());
            for (std::size_t i = 0; i < seq.size(); ++i) {
                total_steps += double(seq[i].steps);
                if (i == 0) first_steps += double(seq[i].steps);
            }
            for (std::size_t i = 0; i < seq.size();) {
                if (!seq[i].empty) {
                    runs[0] += 1, leaves[0] += 1, steps[0] += double(i ? seq[i].steps : 0);
                    ++i;
                    continue;
                }
                std::size_t j = i;
                double st = 0;
                while (j < seq.size() && seq[j].empty) st += double(j ? seq[j].steps : 0), ++j;
                const std::size_t len = j - i;
                const int c = len >= 4 ? 4 : int(len);
                runs[c] += 1, leaves[c] += double(len), steps[c] += st;
                if (j < seq.size()) step_after_run[c] += double(seq[j].steps);
                i = j;
            }
        }
        const double n = double(rays.size());
        std::printf("%s: per ray %.3f leaves, %.3f empty, %.2f descent steps (%.2f of them the first descent)\n", argv[f],
                    total_leaves / n, (total_leaves - leaves[0]) / n, total_steps / n, first_steps / n);
        const char* names[5] = {"non-empty", "run 1", "run 2", "run 3", "run >=4"};
        for (int c = 0; c < 5; ++c)
            std::printf("  %-9s runs/ray %.3f leaves/ray %.3f descent steps into them/ray %.3f, into the leaf after/ray %.3f\n",
                        names[c], runs[c] / n, leaves[c] / n, steps[c] / n, step_after_run[c] / n);
        // rope steps (leaf entries after the first) a skip over runs of >= 2 would save: a run of L
        // leaves entered by one jump instead of L steps (the step into its first leaf and out of it stay)
        const double saved = (leaves[2] - runs[2]) + (leaves[3] - runs[3]) + (leaves[4] - runs[4]);
        std::printf("  leaf entries per ray %.3f; entries a skip over runs >= 2 saves at most %.3f (%.1f%%)\n", total_leaves / n,
                    saved / n, 100.0 * saved / total_leaves);
        if (repeats > 0) time_oracle(tree, rays, repeats);
    }
    return 0;
}
