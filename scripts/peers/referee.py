"""The referee: plain float64 brute force over every triangle, on a sample of the queries, to say
who is right where the libraries disagree. It is written for being obviously right, not fast:
Moller-Trumbore with inclusive edges for rays, the region test of Ericson's "Real-Time Collision
Detection" (5.1.5) for closest points, and the sum of solid angles (Van Oosterom and Strackee) for
the winding number, whose value >= 0.5 is inside on a closed mesh."""
import numpy as np


class Referee:
    def __init__(self, verts, faces):
        v = verts.astype(np.float64)
        f = faces.astype(np.int64)
        self.a, self.b, self.c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        self.e1, self.e2 = self.b - self.a, self.c - self.a

    def _ts(self, o, d, tnear, tfar):
        """t of every triangle the ray crosses in [tnear, tfar] (edges and vertices included)."""
        p = np.cross(d, self.e2)
        det = np.einsum("ij,ij->i", self.e1, p)
        ok = det != 0
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = o - self.a
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, self.e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", self.e2, q) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= tnear) & (t <= tfar)
        return t[hit]

    def closest_t(self, o, d, tnear, tfar):
        ts = self._ts(np.float64(o), np.float64(d), float(tnear), float(tfar))
        return float(ts.min()) if len(ts) else np.inf

    def crossings(self, o, d, tnear, tfar):
        return len(self._ts(np.float64(o), np.float64(d), float(tnear), float(tfar)))

    def distance(self, p):
        """Distance from p to the nearest triangle."""
        p = np.float64(p)
        a, b, c = self.a, self.b, self.c
        ab, ac, ap = b - a, c - a, p - a
        d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
        bp = p - b
        d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
        cp = p - c
        d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        out = np.empty_like(a)
        done = np.zeros(len(a), bool)

        def put(mask, q):
            nonlocal done
            m = mask & ~done
            out[m] = q[m] if q.ndim == 2 else q
            done |= m

        put((d1 <= 0) & (d2 <= 0), a)
        put((d3 >= 0) & (d4 <= d3), b)
        with np.errstate(divide="ignore", invalid="ignore"):
            put((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + (d1 / (d1 - d3))[:, None] * ab)
            put((d6 >= 0) & (d5 <= d6), c)
            put((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + (d2 / (d2 - d6))[:, None] * ac)
            put((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0),
                b + ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None] * (c - b))
            denom = 1.0 / (va + vb + vc)
            put(np.ones(len(a), bool), a + (vb * denom)[:, None] * ab + (vc * denom)[:, None] * ac)
        return float(np.sqrt(((out - p) ** 2).sum(axis=1)).min())

    def winding(self, p):
        p = np.float64(p)
        x, y, z = self.a - p, self.b - p, self.c - p
        lx, ly, lz = (np.linalg.norm(w, axis=1) for w in (x, y, z))
        det = np.einsum("ij,ij->i", x, np.cross(y, z))
        div = (lx * ly * lz + np.einsum("ij,ij->i", x, y) * lz + np.einsum("ij,ij->i", y, z) * lx
               + np.einsum("ij,ij->i", z, x) * ly)
        return float(np.arctan2(det, div).sum() / (2 * np.pi))
