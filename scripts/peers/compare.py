"""One model through every library: builds, the timed rounds and the refereed agreement."""
import statistics
import sys
import time

import numpy as np

from . import meshes, queries
from .arbor_peer import ArborPeer
from .embree_peer import EmbreePeer
from .fcpw_peer import FcpwPeer
from .referee import Referee

# (query, input): the rows of the table, in order.
ROWS = [("closest", "camera"), ("closest", "random"), ("closest", "edge"), ("any", "shadow"),
        ("count", "camera"), ("count", "random"), ("closest_point", "points"), ("inside", "points")]


def agree(query, a, b, ref_scale):
    """Elementwise: do two answers agree? t within 1e-4 of itself (a float32 ray meeting a face at
    a grazing angle leaves that much room: its hit moves by its rounding over the angle's sine),
    distances within 1e-5 of themselves, both plus 1e-6 of the scene's diagonal (ref_scale: that
    diagonal in the query's own units, per query)."""
    if query in ("closest", "closest_point"):
        a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
        both_inf = np.isinf(a) & np.isinf(b)
        with np.errstate(invalid="ignore"):
            rel = 1e-4 if query == "closest" else 1e-5
            close = np.abs(a - b) <= rel * np.minimum(np.abs(a), np.abs(b)) + 1e-6 * ref_scale
        return both_inf | close
    return np.asarray(a) == np.asarray(b)


def reference(ref, query, data, i):
    if query == "closest":
        o, d, tn, tf = data
        return ref.closest_t(o[i], d[i], tn[i], tf[i])
    if query == "any":
        o, d, tn, tf = data
        return np.isfinite(ref.closest_t(o[i], d[i], tn[i], tf[i]))
    if query == "count":
        o, d, tn, tf = data
        return ref.crossings(o[i], d[i], tn[i], tf[i])
    if query == "closest_point":
        return ref.distance(data[i])
    return ref.winding(data[i]) >= 0.5


def run_model(path, name, o):
    verts, faces = meshes.read_obj(path)
    diag = meshes.diagonal(verts)
    closed = meshes.is_closed(faces)
    # Imported here: the referee and agree() (tests/peers_referee_test.py) need no Open3D.
    from .open3d_peer import Open3dPeer
    peers = [ArborPeer(o.threads), Open3dPeer(o.threads), EmbreePeer(o.threads, False), EmbreePeer(o.threads, True)]
    if o.fcpw_shim:
        peers += [FcpwPeer(o.threads, o.fcpw, o.fcpw_shim), FcpwPeer(o.threads, o.fcpw, o.fcpw_shim, True)]
    builds = {p.name: [] for p in peers}
    for r in range(o.rounds):
        for p in peers[r % len(peers):] + peers[:r % len(peers)]:
            builds[p.name].append(p.build(verts, faces))
    if not peers[1].check_mask(verts):
        sys.exit("bench_peers: Open3D misses a ray aimed at the mesh: the ray-mask shim did not take")
    edge_rays, grazing = queries.edge_rays(verts, faces, o.rays, 13)
    inputs = {
        "camera": queries.arbor_rays(o.arbor, path, "primary", o.rays, 11),
        "random": queries.arbor_rays(o.arbor, path, "random", o.rays, 12),
        "edge": edge_rays,
        "shadow": queries.unit_tfar(*queries.arbor_rays(o.arbor, path, "shadow", o.rays, 14)),
        "points": queries.box_points(verts, o.points, 15),
    }
    ref = Referee(verts, faces)
    rng = np.random.default_rng(16)
    rows = []
    for query, kind in ROWS:
        data = inputs[kind]
        if query == "inside" and not closed:
            rows.append({"query": query, "input": kind, "skipped": "the mesh is not closed: inside is not defined"})
            continue
        offering = [p for p in peers if query in p.offers]
        prepared = {p.name: (p.prepare_points(data) if kind == "points" else p.prepare_rays(*data)) for p in offering}
        times = {p.name: [] for p in offering}
        answers = {}
        for r in range(o.rounds):
            for p in offering[r % len(offering):] + offering[:r % len(offering)]:
                t0 = time.perf_counter()
                answers[p.name] = getattr(p, query)(prepared[p.name])
                times[p.name].append((time.perf_counter() - t0) * 1e3)
        n = len(data) if kind == "points" else len(data[0])
        scale = np.full(n, diag) if kind == "points" else diag / np.linalg.norm(data[1].astype(np.float64), axis=1)
        names = [p.name for p in offering]
        differ = np.zeros(n, bool)
        for a in names:
            for b in names:
                if a < b:
                    differ |= ~agree(query, answers[a], answers[b], scale)
        diff_idx = np.flatnonzero(differ)
        picked = np.unique(np.concatenate([diff_idx[:o.sample], rng.choice(n, min(o.sample, n), replace=False)]))
        wrong = {nm: 0 for nm in names}
        ambiguous = 0
        for i in picked:
            truth = reference(ref, query, data, i)
            if query == "inside" and ref.distance(data[i]) < 1e-4 * diag:
                ambiguous += 1  # too near the surface for float32 inputs to have one answer
                continue
            if kind == "edge" and grazing[i]:
                ambiguous += 1  # grazes an outline: either answer is right
                continue
            for nm in names:
                if not agree(query, np.array([answers[nm][i]]), np.array([truth]), scale[i:i + 1])[0]:
                    wrong[nm] += 1
        rows.append({"query": query, "input": kind, "n": n, "ms": {k: statistics.median(v) for k, v in times.items()},
                     "differ": int(len(diff_idx)), "refereed": int(len(picked) - ambiguous), "wrong": wrong,
                     "ambiguous": ambiguous})
        print(f"  {query:13s} {kind:6s} " + "  ".join(f"{k} {statistics.median(v):8.2f} ms" for k, v in times.items())
              + f"  differ {len(diff_idx)}  wrong {wrong}", flush=True)
    return {"name": name, "triangles": len(faces), "closed": closed, "diag": diag,
            "builds": {k: statistics.median(v) for k, v in builds.items()},
            "describe": {p.name: p.describe() for p in peers}, "rows": rows}
