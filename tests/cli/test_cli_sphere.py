"""The paper's sphere test (section 5, Fig. 6) and the feature frequency from --radius and
from a selected region, through the command-line tool."""

import os
import re
import unittest

import numpy as np

import cli_harness as h

FIG6 = dict(s1=10.0, s2=25.0, G0=1.0, G1=30.0, Ginf=0.0)
DESIGN_S1 = r"design: s1 = ([-+.\deE]+)"


def fig6_args():
    return ["--s1", FIG6["s1"], "--s2", FIG6["s2"], "--G0", FIG6["G0"], "--G1", FIG6["G1"], "--Ginf", FIG6["Ginf"]]


class SphereTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("sphere")

    def sphere_file(self, radius, levels, ext="off"):
        path = os.path.join(self.dir, f"sphere-r{radius}-l{levels}.{ext}")
        if not os.path.exists(path):
            v, f = h.icosphere(levels, radius)
            h.WRITERS[ext](path, v, f)
        return path

    def test_eq15_reference_meets_its_five_conditions(self):
        # The five conditions the five numbers stand for (docs/paper-notes.md §2).
        g = lambda s: h.eq15_gain(s, **FIG6)
        self.assertAlmostEqual(g(0), FIG6["G0"], places=12)
        self.assertAlmostEqual(g(FIG6["s1"]), FIG6["G1"], places=9)
        self.assertAlmostEqual((g(FIG6["s1"] + 1e-4) - g(FIG6["s1"] - 1e-4)) / 2e-4, 0, delta=1e-5)
        self.assertAlmostEqual(g(FIG6["s2"]), 1, places=9)
        self.assertAlmostEqual(g(1e12), FIG6["Ginf"], places=6)

    def test_fig6_radius_ratio_is_gain(self):
        for radius, levels in [(0.3, 3), (1.0, 4)]:
            with self.subTest(radius=radius):
                out = os.path.join(self.dir, f"fig6-r{radius}.ply")
                p = h.run("custom", *fig6_args(), self.sphere_file(radius, levels), out)
                self.assertEqual(p.returncode, 0, h.describe(p))
                v = h.read_mesh(out).vertices
                self.assertEqual(len(v), 10 * 4 ** levels + 2)
                ratio = float(np.mean(h.radii(v))) / radius
                expected = abs(h.eq15_gain(2 / radius ** 2, **FIG6))
                self.assertAlmostEqual(ratio / expected, 1, delta=0.02, msg=f"r = {radius}: {ratio} vs G = {expected}")

    def test_radius_sets_s1_and_the_presets_s2_ratio(self):
        source = self.sphere_file(1.0, 3)
        for shape, k in [("sphere", 2.0), ("cylinder", 1.0)]:
            for R in (0.05, 0.4):
                with self.subTest(shape=shape, R=R):
                    p = h.run("exaggerate", "--radius", R, "--feature-shape", shape, source,
                              os.path.join(self.dir, "radius.off"))
                    self.assertEqual(p.returncode, 0, h.describe(p))
                    s1 = h.log_value(p, DESIGN_S1)
                    s2 = h.log_value(p, r"design: s1 = [^,]+, s2 = ([-+.\deE]+)")
                    self.assertAlmostEqual(s1 / (k / R ** 2), 1, places=5)
                    self.assertAlmostEqual(s2 / s1, 60 / 25, places=5)

    def test_radius_sets_the_polezero_feature_corner(self):
        R = 0.2
        p = h.run("polezero", "--radius", R, "--zeros", "100,400", "--poles", "50,800", "--feature-corner", "z2",
                  self.sphere_file(1.0, 3), os.path.join(self.dir, "pz-radius.off"))
        self.assertEqual(p.returncode, 0, h.describe(p))
        s = 2 / R ** 2  # 50: z2 = 50, so every corner is scaled by 50/400
        self.assertAlmostEqual(h.log_value(p, r"corner z2 = ([-+.\deE]+) from the feature radius"), s, places=4)
        self.assertIn("zeros 12.5, 50, poles 6.25, 100", p.stdout)

    def test_selected_whole_sphere_gives_2_over_r2(self):
        for R, levels in [(0.3, 3), (2.0, 3)]:
            source = self.sphere_file(R, levels)
            for region in (["--select-sphere", f"0,0,0,{1.01 * R}"],
                           ["--select-box", f"{-1.01 * R},{-1.01 * R},{-1.01 * R},{1.01 * R},{1.01 * R},{1.01 * R}"]):
                with self.subTest(R=R, region=region[0]):
                    p = h.run("lowpass", *region, source, os.path.join(self.dir, "selected.off"))
                    self.assertEqual(p.returncode, 0, h.describe(p))
                    self.assertIn(f": {20 * 4 ** levels} faces", p.stderr)  # every face selected
                    self.assertAlmostEqual(h.log_value(p, DESIGN_S1) / (2 / R ** 2), 1, delta=0.05)

    def test_selected_cap_is_measured(self):
        # A cap of a unit sphere: |z| > 0.8 leaves a disc of radius 0.6 around the pole.
        p = h.run("measure", "--select-box", "-2,-2,0.8,2,2,2", self.sphere_file(1.0, 4))
        self.assertEqual(p.returncode, 0, h.describe(p))
        r = float(re.search(r"measure: r = ([-+.\deE]+)", p.stdout).group(1))
        self.assertAlmostEqual(r, 0.6, delta=0.05)

    def test_georeferenced_selection_measures_the_same(self):
        # A 5 cm cap on a scan stored in UTM metres: the measured frequency must not depend on
        # coordinates of ~4e6 (one-pass second moments would cancel to rounding noise there).
        R = 0.05
        v, f = h.icosphere(4, R)
        offset = np.array([5e5, 4e6, 1e2])
        local, far = os.path.join(self.dir, "cap-local.off"), os.path.join(self.dir, "cap-utm.off")
        h.write_off(local, v, f)
        h.write_off(far, v + offset, f)
        box = [-2 * R, -2 * R, 0.5 * R, 2 * R, 2 * R, 2 * R]
        frequencies = []
        for path, shift in ((local, np.zeros(3)), (far, offset)):
            corners = np.concatenate([box[:3] + shift, box[3:] + shift])
            p = h.run("measure", "--select-box", ",".join("%.17g" % c for c in corners), path)
            self.assertEqual(p.returncode, 0, h.describe(p))
            frequencies.append(float(re.search(r"sphere-like s = 2/r\^2 = ([-+.\deE]+)", p.stdout).group(1)))
        self.assertAlmostEqual(frequencies[1] / frequencies[0], 1, delta=1e-6)


if __name__ == "__main__":
    unittest.main()
