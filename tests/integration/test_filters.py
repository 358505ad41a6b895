"""(a) Every GeoFilter entry runs by name through meshlabserver, logs, and moves the mesh by
the gain the paper's transfer function gives.

Input: filter_create's icosphere (642 vertices) with seeded radial noise, scaled to a radius r
chosen per filter. Its coordinate functions are the eigenmodes with s = 2/r^2, so the mean
radius after a filter is about r |G(2/r^2)|, checked against eq. 15/16 of the test references.
Each r puts 2/r^2 where G is far from 1 (a filter that does nothing fails) and far from G at
1/r^2 and 4/r^2 (a Laplacian off by a factor 2 fails); the test checks that margin itself.
"""

import os
import unittest

import numpy as np

import geofilter_harness as h

NOISE = 0.005  # of the radius: small enough that the mean radius still follows G(2/r^2)

# Sphere frequency 2/r^2 per filter (default parameters unless PARAMETERS says otherwise):
# s1 where |G1 - 1| is large (an extremum, so the mesh's small eigenvalue error barely
# matters), else a frequency well inside the pass or stop band.
SPHERE_FREQUENCY = {
    "GeoFilter: Lowpass": 200.0,          # stop band: G = 0.19 (G1 = 1.1 is too close to 1)
    "GeoFilter: Bandpass": 25.0,          # s1: G = 2
    "GeoFilter: Highpass": 2.0,           # below s2 = 25: G = 0.33
    "GeoFilter: Notch": 630.0,            # s1: G = 0.01
    "GeoFilter: Band Exaggeration": 25.0, # s1: G = 3
    "GeoFilter: Custom": 60.0,            # s1: G = 2
    "GeoFilter: Pole-Zero": 40.0,         # between the poles below: G = 0.22
}
# The default pole-zero filter (a shallow band stop, G >= 0.72 everywhere) cannot tell s from
# 2s; two poles and no zeros can.
PARAMETERS = {
    "GeoFilter: Pole-Zero": dict(z1=0.0, z2=0.0, z3=0.0, z4=0.0, p1=20.0, p2=80.0, p3=0.0, p4=0.0),
}
# The presets' reference designs (the paper's figures), typed: the frequencies of eq. 15 as a
# script sets them. A radius instead gives the same design (test_sizes.py, the unit tests).
for _f in h.filter_table.TABLE:
    if _f["kind"] == "SecondOrder":
        PARAMETERS[_f["name"]] = dict(s1=_f["reference"]["s1"], s2=_f["reference"]["s2"])
# Mean radius / r may differ from |G(2/r^2)| by 1% of |G| (the level-3 icosphere's eigenvalue
# error, float32 PLY coordinates) plus 0.1% (what the radial noise leaves in the mean); the
# differences seen are below 0.2% of |G|.
RELATIVE_TOLERANCE, ABSOLUTE_TOLERANCE = 0.01, 0.001


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
        cls.faces = mesh.faces
        r = np.linalg.norm(mesh.vertices, axis=1)
        if len(mesh.vertices) != 642 or np.max(np.abs(r - 1)) > 1e-6:
            raise AssertionError(f"filter_create Sphere is not the expected icosphere: {len(mesh.vertices)} vertices,"
                                 f" radii {r.min()}..{r.max()}")
        rng = np.random.default_rng(7)
        cls.unit_noisy = mesh.vertices * (1 + NOISE * rng.uniform(-1, 1, len(r)))[:, None]
        cls.inputs = {}
        cls.input, cls.input_path = cls.noisy_sphere(1.0)

    @classmethod
    def noisy_sphere(cls, radius):
        """The noisy icosphere scaled to `radius`, as MeshLab will read it (floats)."""
        if radius not in cls.inputs:
            path = os.path.join(cls.dir, f"noisy-r{radius:.6g}.ply")
            h.write_ply_ascii(path, h.PlyMesh(cls.unit_noisy * radius, cls.faces))
            cls.inputs[radius] = (h.read_ply(path), path)
        return cls.inputs[radius]

    def run_filter(self, steps, tag, extra_outputs=(), input_path=None):
        out = os.path.join(self.dir, tag + ".ply")
        run = h.run_meshlabserver(self.dir, steps, inputs=[input_path or self.input_path],
                                  outputs=[(out, None)] + list(extra_outputs), script_name=tag + ".mlx")
        self.assertEqual(run.returncode, 0, run.describe())
        return run, h.read_ply(out)

    def check_filtered(self, name, gain):
        """Runs `name` on a sphere of frequency SPHERE_FREQUENCY[name]; `gain(s)` is the
        reference transfer function for the parameters used."""
        s = SPHERE_FREQUENCY[name]
        radius = np.sqrt(2 / s)
        expected = abs(gain(s))
        tolerance = RELATIVE_TOLERANCE * expected + ABSOLUTE_TOLERANCE
        # The test's own power: doing nothing (gain 1) and a Laplacian scaled by 2 or 1/2
        # (the sphere then at s/2 or 2s) are each at least 4 tolerances away.
        for wrong, label in [(1.0, "identity"), (abs(gain(s / 2)), "G(s/2)"), (abs(gain(2 * s)), "G(2s)")]:
            self.assertGreater(abs(wrong - expected), 4 * tolerance,
                               f"{name}: s = {s} cannot tell |G| = {expected} from the {label} {wrong}")

        tag = name.split(": ")[1].replace(" ", "_").replace("-", "_").lower()
        mesh, path = self.noisy_sphere(radius)
        run, out = self.run_filter([h.geofilter(name, useSelection=False, **PARAMETERS.get(name, {}))], tag,
                                   input_path=path)
        lines = [l for l in run.log if l.startswith(name + ": ")]
        self.assertTrue(any("peak |G|" in l for l in lines), run.describe())
        self.assertTrue(any(": solver " in l for l in lines), run.describe())
        self.assertEqual(out.vertices.shape, mesh.vertices.shape)
        np.testing.assert_array_equal(out.faces, mesh.faces)
        ratio = np.mean(h.radii(out.vertices)) / radius
        self.assertAlmostEqual(ratio, expected, delta=tolerance,
                               msg=f"{name}: mean radius / r = {ratio} vs |G(2/r^2)| = {expected} (r = {radius:.4g})")
        return mesh, out

    def test_second_order_filters(self):
        for name in h.SECOND_ORDER:
            with self.subTest(filter=name):
                v = {**values(name), **PARAMETERS[name]}
                mesh, out = self.check_filtered(
                    name, lambda s: h.eq15_gain(s, v["s1"], v["s2"], v["G0"], v["G1"], v["Ginf"]))
                if name == "GeoFilter: Lowpass":
                    # G -> 0 at high frequency: the noise must mostly go, relative to the
                    # (shrunk) radius.
                    before = np.std(h.radii(mesh.vertices)) / np.mean(h.radii(mesh.vertices))
                    after = np.std(h.radii(out.vertices)) / np.mean(h.radii(out.vertices))
                    self.assertLess(after, 0.5 * before, f"relative radial noise {before} -> {after}")

    def test_pole_zero(self):
        name = "GeoFilter: Pole-Zero"
        v = {**values(name), **PARAMETERS[name]}
        self.check_filtered(name, lambda s: h.eq16_gain(s, v["G0"], [v[f"z{i}"] for i in range(1, 5)],
                                                        [v[f"p{i}"] for i in range(1, 5)]))

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
