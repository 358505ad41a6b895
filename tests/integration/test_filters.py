"""(a) Every GeoFilter entry runs by name through meshlabserver, logs, and moves the mesh.

Input: filter_create's icosphere (r = 1, 642 vertices) with seeded radial noise. Its
coordinate functions are the eigenmodes with s = 2/r^2 = 2, so the mean radius after a
filter is about |G(2)|, which is checked against eq. 15/16 computed in the harness.
"""

import os
import unittest

import numpy as np

import geofilter_harness as h

NOISE = 0.005  # of the radius: small enough that the mean radius still follows G(2)


def values(name):
    return {p.name: p.default for p in h.FILTERS[name]}


class EveryFilter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir_for(cls.__module__ + ".EveryFilter")
        clean = os.path.join(cls.dir, "sphere.ply")
        run = h.run_meshlabserver(cls.dir, [h.sphere(1.0, 3)], outputs=[(clean, None)], script_name="sphere.mlx")
        if run.returncode != 0:
            raise AssertionError("creating the input sphere failed\n" + run.describe())
        mesh = h.read_ply(clean)
        r = np.linalg.norm(mesh.vertices, axis=1)
        if len(mesh.vertices) != 642 or np.max(np.abs(r - 1)) > 1e-6:
            raise AssertionError(f"filter_create Sphere is not the expected icosphere: {len(mesh.vertices)} vertices,"
                                 f" radii {r.min()}..{r.max()}")
        rng = np.random.default_rng(7)
        mesh.vertices = mesh.vertices * (1 + NOISE * rng.uniform(-1, 1, len(r)))[:, None]
        cls.input = mesh
        cls.input_path = os.path.join(cls.dir, "noisy.ply")
        h.write_ply_ascii(cls.input_path, mesh)
        # Read back what MeshLab will see (floats), so that comparisons are exact.
        cls.input = h.read_ply(cls.input_path)

    def run_filter(self, steps, tag, extra_outputs=()):
        out = os.path.join(self.dir, tag + ".ply")
        run = h.run_meshlabserver(self.dir, steps, inputs=[self.input_path],
                                  outputs=[(out, None)] + list(extra_outputs), script_name=tag + ".mlx")
        self.assertEqual(run.returncode, 0, run.describe())
        return run, h.read_ply(out)

    def check_filtered(self, name, expected_gain):
        tag = name.split(": ")[1].replace(" ", "_").lower()
        run, out = self.run_filter([h.geofilter(name, useSelection=False)], tag)
        lines = [l for l in run.log if l.startswith(name + ": ")]
        self.assertTrue(any("peak |G|" in l for l in lines), run.describe())
        self.assertTrue(any(": solver " in l for l in lines), run.describe())
        self.assertEqual(out.vertices.shape, self.input.vertices.shape)
        np.testing.assert_array_equal(out.faces, self.input.faces)
        self.assertGreater(np.max(np.abs(out.vertices - self.input.vertices)), 1e-3, "the mesh did not move")
        mean_r = np.mean(h.radii(out.vertices))
        self.assertAlmostEqual(mean_r, abs(expected_gain), delta=0.03,
                               msg=f"mean radius {mean_r} vs |G(2)| = {abs(expected_gain)}")
        return out

    def test_second_order_filters(self):
        for name in h.SECOND_ORDER:
            with self.subTest(filter=name):
                v = values(name)
                g2 = h.eq15_gain(2.0, v["s1"], v["s2"], v["G0"], v["G1"], v["Ginf"])
                out = self.check_filtered(name, g2)
                if name == "GeoFilter: Lowpass":
                    # G -> 0 at high frequency: the noise must mostly go.
                    before = np.std(h.radii(self.input.vertices))
                    after = np.std(h.radii(out.vertices))
                    self.assertLess(after, 0.5 * before, f"radial noise {before} -> {after}")

    def test_pole_zero(self):
        v = values("GeoFilter: Pole-Zero")
        g2 = h.eq16_gain(2.0, v["G0"], [v[f"z{i}"] for i in range(1, 5)], [v[f"p{i}"] for i in range(1, 5)])
        self.check_filtered("GeoFilter: Pole-Zero", g2)

    def test_measure_selected_feature(self):
        name = "GeoFilter: Measure Selected Feature"
        ellipsoid = os.path.join(self.dir, "ellipsoid.ply")
        run, current = self.run_filter([h.select_faces("(z0 > 0.5) && (z1 > 0.5) && (z2 > 0.5)"), h.geofilter(name)],
                                       "measure", extra_outputs=[(ellipsoid, "x")])
        self.assertTrue(any(l.startswith(name + ": feature frequency") for l in run.log), run.describe())
        self.assertTrue(any(l.startswith(name + ": feature: ") for l in run.log), run.describe())
        # Measuring leaves the measured mesh alone and stays on it (the saved current layer).
        np.testing.assert_array_equal(current.vertices, self.input.vertices)
        # The new layer is the fitted ellipsoid: an icosphere (level 3) around the cap z > 0.5.
        e = h.read_ply(ellipsoid)
        self.assertEqual(len(e.vertices), 642)
        lo, hi = e.vertices.min(axis=0), e.vertices.max(axis=0)
        base = np.sqrt(1 - 0.5 ** 2)
        for k in range(2):
            self.assertAlmostEqual(lo[k], -base, delta=0.1)
            self.assertAlmostEqual(hi[k], base, delta=0.1)
        self.assertAlmostEqual(lo[2], 0.5, delta=0.1)
        self.assertAlmostEqual(hi[2], 1.0, delta=0.1)


if __name__ == "__main__":
    unittest.main()
