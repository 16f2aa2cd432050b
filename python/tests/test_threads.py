"""threads= on every query (the same bits for any count), thread counts above the cores (no
oneTBB warning), and the scene's lock (a build waiting behind queries gets in)."""
import os
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import arbor
from conftest import random_rays


def every_query(s, o, d, pts, threads):
    """The answers of every query, as bytes, on `threads` threads."""
    hits = s.intersect(o, d, tnear=0.01, threads=threads)
    normals = s.intersect(o, d, threads=threads, normals=True)
    occ = s.occluded(o, d, tfar=2.0, threads=threads)
    rows, counts = s.intersect_all(o, d, max_hits=3, threads=threads, normals=True)
    near = s.closest_point(pts, max_distance=0.3, threads=threads)
    ins = s.inside(pts, threads=threads)
    return [a.tobytes() for a in (hits, normals, occ, rows, counts, near, ins)]


def test_results_are_bit_identical_for_any_thread_count(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah", threads=2)
    o, d = random_rays(s, 20_000, seed=12)
    lo, hi = s.bounds
    pts = (lo + np.random.default_rng(3).random((3000, 3)) * (hi - lo)).astype(np.float32)
    ref = every_query(s, o, d, pts, 1)
    h = s.intersect(o, d)
    assert 1000 < np.count_nonzero(h["prim"] != arbor.MISS) < 19_000
    for threads in (2, 3, 0, 4 * (os.cpu_count() or 1) + 3, np.int64(2)):
        assert every_query(s, o, d, pts, threads) == ref, threads


@pytest.mark.parametrize("call", ["intersect", "occluded", "intersect_all", "closest_point", "inside"])
def test_threads_errors_name_the_argument(box_scene, call):
    f = getattr(box_scene, call)
    args = (np.zeros((2, 3)),) if call in ("closest_point", "inside") else (np.zeros((2, 3)), np.ones((2, 3)))
    for bad, kind in (("2", TypeError), (1.5, TypeError), (None, TypeError), (True, TypeError), (-1, ValueError),
                      (np.array([1, 2]), TypeError)):
        with pytest.raises(kind, match=r"^threads: expected an int >= 0 \(0 = the scene's threads\)") as e:
            f(*args, threads=bad)
        assert "\n" not in str(e.value)


def test_thread_counts_above_the_cores_print_nothing(spot, tmp_path):
    # oneTBB warns once per process, on stderr (fd 2, from C++), when an arena asks for more
    # workers than the machine has: a fresh interpreter whose fd 2 is captured.
    script = textwrap.dedent(f"""
        import numpy as np, arbor
        s = arbor.Scene.load({str(spot)!r})
        many = 64 * 1024
        s.build("bvh-sah", threads=many)
        o = np.zeros((5000, 3), np.float32); d = np.ones((5000, 3), np.float32)
        s.intersect(o, d, threads=many); s.occluded(o, d, threads=many + 1)
        s.intersect_all(o, d, threads=many + 2); s.closest_point(o, threads=many + 3); s.inside(o, threads=many + 4)
        s.build("lbvh", threads=2**40)
        import os; os.write(1, b"done")
        """)
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, env=os.environ, timeout=120)
    assert run.returncode == 0 and run.stdout == b"done", run.stderr
    assert run.stderr == b""


def test_the_stderr_capture_sees_what_cpp_writes_to_fd_2():
    # The check above would see a warning: a write to fd 2 below Python's sys.stderr is captured.
    run = subprocess.run([sys.executable, "-c", "import os; os.write(2, b'TBB Warning: x')"], capture_output=True)
    assert run.stderr == b"TBB Warning: x"


def test_build_errors_are_one_line_type_errors_naming_the_argument(box_scene):
    cases = [({"accel": None}, TypeError, "accel: expected a str"),
             ({"threads": "2"}, TypeError, r"threads: expected an int >= 0 \(0 = all cores\), got str"),
             ({"threads": 2.0}, TypeError, "threads: expected an int"),
             ({"max_memory": 1.5}, TypeError, "max_memory: expected a number of bytes"),
             ({"threads": -3}, ValueError, "threads: expected an int >= 0"),
             ({"accel": "octree"}, ValueError, "unknown structure 'octree'")]
    for kw, kind, msg in cases:
        with pytest.raises(kind, match=msg) as e:
            box_scene.build(**kw)
        assert "\n" not in str(e.value), kw
    with pytest.raises(TypeError, match=r"^max_hits: expected an int >= 0, got float$"):
        box_scene.intersect_all(np.zeros((1, 3)), np.ones((1, 3)), max_hits=1.5)
    box_scene.build("bvh-sah", threads=np.uint8(1))
    assert box_scene.accel == "bvh-sah"


def test_a_build_gets_in_while_three_threads_keep_querying(spot):
    # Three threads query back to back, so at any moment one of them holds the scene's shared
    # lock: a lock that lets new readers pass a waiting writer (std::shared_mutex here) kept
    # build() out for 0.6-0.9 s, while dozens of queries that started after it overtook it. The
    # writer-first lock lets it in once the queries running finish: a query that starts after
    # build() is called ends after it returns, but for one per reader that slips in between the
    # time stamp and the moment build() waits (the GIL may pass to a reader in between).
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 40_000, seed=13)
    t0 = time.perf_counter()
    s.intersect(o, d)
    one_query = time.perf_counter() - t0
    stop = threading.Event()
    calls = [[], [], []]  # (start, end) of each query, per thread

    def hammer(i):
        while not stop.is_set():
            start = time.perf_counter()
            s.intersect(o, d)
            calls[i].append((start, time.perf_counter()))
    readers = [threading.Thread(target=hammer, args=(i,)) for i in range(3)]
    for t in readers:
        t.start()
    waits, overtakers = [], 0
    try:
        for accel in ("lbvh", "bvh-median", "bvh-sah"):
            time.sleep(0.2)
            t0 = time.perf_counter()
            s.build(accel)
            t1 = time.perf_counter()
            waits.append(t1 - t0)
            overtakers += sum(1 for c in calls for start, end in c if t0 < start and end < t1)
            assert s.accel == accel
        time.sleep(0.2)
    finally:
        stop.set()
        for t in readers:
            t.join()
    print(f"one query {one_query * 1e3:.1f} ms; builds waited and ran {[round(w * 1e3, 1) for w in waits]} ms; "
          f"{overtakers} queries overtook them")
    assert all(len(c) > 10 for c in calls)  # every reader kept querying, before, between and after
    assert max(waits) < 1.0, waits
    assert overtakers <= 3 * len(waits), overtakers
