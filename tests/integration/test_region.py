"""(e) Filtering only a region through meshlabserver.

A cap of an icosphere is selected with Conditional Face Selection and a GeoFilter filter is
run with region = 1. Checked against an independent numpy reference of the documented math
(README, "Filtering a region"): weight w = 1 - 3t^2 + 2t^3 of t = d / blendWidth, d the
edge-path distance to the selected faces (Dijkstra); D = {w > 0} filtered as its own domain
with every other vertex fixed, p' = h + V G(Lambda) V^T M (p - h) from a dense eigen
decomposition of the cotangent Laplacian restricted to D; result p + w (p' - p).
"""

import heapq
import re
import os
import unittest

import numpy as np

import geofilter_harness as h

CAP = "(z0 > 0.6) && (z1 > 0.6) && (z2 > 0.6)"
DESIGN = dict(s1=20.0, s2=50.0, G0=1.0, G1=3.0, Ginf=0.9)


def cotan_laplacian(p, faces):
    """K (cotangent stiffness, K_ij = -(cot a + cot b) / 2) and the lumped mass (area / 3)."""
    n = len(p)
    k = np.zeros((n, n))
    mass = np.zeros(n)
    for f in faces:
        for c in range(3):
            i, j, o = f[c], f[(c + 1) % 3], f[(c + 2) % 3]
            u, v = p[i] - p[o], p[j] - p[o]
            cot = np.dot(u, v) / np.linalg.norm(np.cross(u, v))
            k[i, j] -= cot / 2
            k[j, i] -= cot / 2
            k[i, i] += cot / 2
            k[j, j] += cot / 2
        mass[f] += np.linalg.norm(np.cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]])) / 6
    return k, mass


def weight(p, faces, selected, width):
    dist = np.full(len(p), np.inf)
    heap = []
    for f in selected:
        for v in faces[f]:
            dist[v] = 0.0
            heap.append((0.0, v))
    neighbours = [set() for _ in range(len(p))]
    for f in faces:
        for c in range(3):
            neighbours[f[c]].update((f[(c + 1) % 3], f[(c + 2) % 3]))
    while heap:
        d, v = heapq.heappop(heap)
        if d > dist[v]:
            continue
        for u in neighbours[v]:
            du = d + np.linalg.norm(p[u] - p[v])
            if du < dist[u]:
                dist[u] = du
                heapq.heappush(heap, (du, u))
    t = np.clip(dist / width, 0, 1)
    return np.where(dist < width, 1 - 3 * t ** 2 + 2 * t ** 3, 0.0)


def reference(p, faces, w, design):
    k, mass = cotan_laplacian(p, faces)
    free = np.flatnonzero(w > 0)
    fixed = np.flatnonzero(w == 0)
    kff = k[np.ix_(free, free)]
    h_free = np.linalg.solve(kff, -k[np.ix_(free, fixed)] @ p[fixed])
    # K v = lambda M v through the symmetric M^-1/2 K M^-1/2.
    s = 1 / np.sqrt(mass[free])
    lam, q = np.linalg.eigh(s[:, None] * kff * s[None, :])
    gains = h.eq15_gain(np.maximum(lam, 0), design["s1"], design["s2"], design["G0"], design["G1"], design["Ginf"])
    detail = (p[free] - h_free) / s[:, None]          # M^1/2 (p - h)
    filtered = h_free + s[:, None] * (q @ (gains[:, None] * (q.T @ detail)))
    out = p.copy()
    out[free] = p[free] + w[free, None] * (filtered - p[free])
    return out


def dihedral_changes(before, after, faces):
    """|change of the angle between the two face normals| per edge shared by two faces."""
    def normals(p):
        n = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
        return n / np.linalg.norm(n, axis=1)[:, None]
    edges = {}
    for fi, f in enumerate(faces):
        for c in range(3):
            edges.setdefault(tuple(sorted((f[c], f[(c + 1) % 3]))), []).append(fi)
    nb, na = normals(before), normals(after)
    out = {}
    for e, fs in edges.items():
        if len(fs) == 2:
            angle = lambda n: np.arctan2(np.linalg.norm(np.cross(n[fs[0]], n[fs[1]])), np.dot(n[fs[0]], n[fs[1]]))
            out[e] = abs(angle(na) - angle(nb))
    return out


def selected_faces(p, faces):
    return [i for i, f in enumerate(faces) if np.all(p[f, 2] > 0.6)]


class RegionThroughMeshlabserver(unittest.TestCase):
    def run_steps(self, tag, steps, expect_ok=True):
        d = h.workdir_for(f"{self.id()}.{tag}")
        out = os.path.join(d, "out.ply")
        run = h.run_meshlabserver(d, steps, outputs=[(out, None)])
        if expect_ok:
            self.assertEqual(run.returncode, 0, run.describe())
            return run, h.read_ply(out)
        return run, None

    def test_selected_region_matches_the_dense_reference_and_leaves_the_rest_bit_for_bit(self):
        _, original = self.run_steps("in", [h.sphere(1.0, 3)])
        filt = h.geofilter("GeoFilter: Band Exaggeration", useSelection=False, region=1, blendWidth=0.4, **DESIGN)
        run, out = self.run_steps("region", [h.sphere(1.0, 3), h.select_faces(CAP), filt])
        p, faces = original.vertices, original.faces
        np.testing.assert_array_equal(out.faces, faces)
        sel = selected_faces(p, faces)
        self.assertGreater(len(sel), 20)
        w = weight(p, faces, sel, 0.4)
        ref = reference(p, faces, w, DESIGN)
        diag = np.linalg.norm(p.max(axis=0) - p.min(axis=0))
        error = np.linalg.norm(out.vertices - ref, axis=1).max()
        self.assertLess(error, 1e-6 * diag, f"max error {error}\n" + run.describe())
        outside = w == 0
        self.assertGreater(outside.sum(), len(p) // 2)
        np.testing.assert_array_equal(out.vertices[outside], p[outside])  # the PLY's float32, bit for bit
        self.assertGreater(np.linalg.norm(out.vertices - p, axis=1).max(), 0.01, "the cap must change")

        # Crease measure: the largest change of dihedral angle on the border (edges from D to
        # the fixed rest) stays within the largest the same filter makes inside the region
        # (edges with w = 1 at both ends).
        changes = dihedral_changes(p, out.vertices, faces)
        border = max(c for e, c in changes.items() if (w[e[0]] > 0) != (w[e[1]] > 0))
        interior = max(c for e, c in changes.items() if w[e[0]] == 1 and w[e[1]] == 1)
        print(f"crease measure through meshlabserver: border {border:.4g} rad, region interior {interior:.4g} rad")
        self.assertLessEqual(border, interior)

    def test_selection_gives_frequency_and_region(self):
        _, original = self.run_steps("in", [h.sphere(1.0, 3)])
        run, out = self.run_steps("same", [h.sphere(1.0, 3), h.select_faces(CAP),
                                           h.geofilter("GeoFilter: Band Exaggeration", useSelection=True, region=1)])
        self.assertTrue(any(re.search(r"s1 = \S+ from \d+ selected faces", l) for l in run.log), run.describe())
        self.assertTrue(any("auto: the feature radius" in l for l in run.log), run.describe())
        moved = np.linalg.norm(out.vertices - original.vertices, axis=1) > 0
        self.assertTrue(moved.any())
        # The cap (z > 0.6, radius ~0.8) and a band of its radius: the lower part stays.
        self.assertTrue(np.all(original.vertices[moved, 2] > -0.3), "only the cap and its band may move")
        self.assertGreater(np.sum(original.vertices[:, 2] < -0.3), 100)

    def test_quality_weight_one_is_the_whole_mesh_filter_and_zero_changes_nothing(self):
        filt = lambda region: h.geofilter("GeoFilter: Lowpass", useSelection=False, region=region)
        _, whole = self.run_steps("whole", [h.sphere(1.0, 3), filt(0)])
        _, one = self.run_steps("one", [h.sphere(1.0, 3), h.vertex_quality("1"), filt(2)])
        _, original = self.run_steps("in", [h.sphere(1.0, 3)])
        run, zero = self.run_steps("zero", [h.sphere(1.0, 3), h.vertex_quality("0"), filt(2)])
        np.testing.assert_array_equal(one.vertices, whole.vertices)
        self.assertGreater(np.abs(whole.vertices - original.vertices).max(), 1e-3)
        np.testing.assert_array_equal(zero.vertices, original.vertices)
        self.assertTrue(any("nothing changed" in l for l in run.log), run.describe())

    def expect_refusal(self, tag, steps, needle):
        run, _ = self.run_steps(tag, steps, expect_ok=False)
        self.assertNotEqual(run.returncode, 0, run.describe())
        errors = [l for l in run.log if l.startswith("GeoFilter error: ")]
        self.assertEqual(len(errors), 1, run.describe())
        self.assertIn(needle, errors[0], run.describe())

    def test_refusals(self):
        self.expect_refusal("nosel", [h.sphere(1.0, 2), h.geofilter("GeoFilter: Lowpass", useSelection=False, region=1)],
                            "no faces are selected")
        self.expect_refusal("nan", [h.sphere(1.0, 2), h.vertex_quality("sqrt(-1)"),
                                    h.geofilter("GeoFilter: Lowpass", useSelection=False, region=2)], "NaN")


if __name__ == "__main__":
    unittest.main()
