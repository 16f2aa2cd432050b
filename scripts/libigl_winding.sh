#!/usr/bin/env bash
# libigl's fast winding number (Barill et al. 2018, its triangle-soup path) on the same mesh and
# points as scripts/bench_winding.py, for comparison: time for all points and error against arbor's
# exact sum on the sample, at expansion order 0 (first order: the dipole arbor uses) and 2
# (libigl's default), accuracy_scale (beta) 2. Nothing of libigl is kept in the repository: give
# the path of a libigl checkout (its include/ is used header-only) and Eigen's headers (Debian:
# libeigen3-dev).
#
#   scripts/libigl_winding.sh LIBIGL_DIR [THREADS]
# with PYTHONPATH pointing at the arbor module (build/release/python).
set -euo pipefail
igl=${1:?usage: $0 LIBIGL_DIR [THREADS]}
threads=${2:-2}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$here/bench_winding.py" --threads "$threads" --dump "$work" >"$work/arbor.txt"
cat "$work/arbor.txt"
cat >"$work/fwn.cpp" <<'CPP'
#include <igl/fast_winding_number.h>
#include <Eigen/Core>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>
template <class T> std::vector<T> read(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    std::vector<T> v(std::size_t(in.tellg()) / sizeof(T));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
    return v;
}
using Rows = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
using IRows = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
int main(int, char** argv) {
    const std::string dir = argv[1];
    auto v = read<float>(dir + "/V.f32"), q = read<float>(dir + "/Q.f32"), s = read<float>(dir + "/S.f32");
    auto f = read<int>(dir + "/F.i32");
    const Rows V = Eigen::Map<Rows>(v.data(), Eigen::Index(v.size() / 3), 3);
    const IRows F = Eigen::Map<IRows>(f.data(), Eigen::Index(f.size() / 3), 3);
    const Rows Q = Eigen::Map<Rows>(q.data(), Eigen::Index(q.size() / 3), 3);
    const Rows S = Eigen::Map<Rows>(s.data(), Eigen::Index(s.size() / 3), 3);
    for (int order : {0, 2}) {
        const auto t0 = std::chrono::steady_clock::now();
        igl::FastWindingNumberBVH bvh;
        igl::fast_winding_number(V, F, order, bvh);
        const auto t1 = std::chrono::steady_clock::now();
        const std::clock_t c1 = std::clock();
        Eigen::VectorXf W, WS;
        igl::fast_winding_number(bvh, 2.0f, Q, W);
        const auto t2 = std::chrono::steady_clock::now();
        const std::clock_t c2 = std::clock();
        igl::fast_winding_number(bvh, 2.0f, S, WS);
        std::ofstream(dir + "/S_igl" + std::to_string(order) + ".f32", std::ios::binary)
            .write(reinterpret_cast<const char*>(WS.data()), std::streamsize(WS.size() * sizeof(float)));
        std::printf("libigl order %d: precompute %.3f s, %zu points %.3f s (cpu %.3f s)\n", order,
                    std::chrono::duration<double>(t1 - t0).count(), std::size_t(Q.rows()),
                    std::chrono::duration<double>(t2 - t1).count(), double(c2 - c1) / CLOCKS_PER_SEC);
    }
}
CPP
g++ -std=c++17 -O3 -march=native -DNDEBUG -I"$igl/include" -I/usr/include/eigen3 "$work/fwn.cpp" -o "$work/fwn" -lpthread
IGL_NUM_THREADS=$threads "$work/fwn" "$work"
python3 - "$work" <<'PY'
import sys, numpy as np
d = sys.argv[1]
exact = np.fromfile(d + "/S_exact.f64", "<f8")
for order in (0, 2):
    w = np.fromfile(f"{d}/S_igl{order}.f32", "<f4").astype(np.float64)
    e = np.abs(w - exact)
    print(f"libigl order {order}: max abs error {e.max():.2e}, mean {e.mean():.2e}, "
          f"inside wrong {np.count_nonzero((w >= 0.5) != (exact >= 0.5))} of {len(exact)}")
PY
