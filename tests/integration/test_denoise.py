"""The Butterworth Lowpass and Denoise filters by name through meshlabserver (issue 10).

A sphere of radius r is the eigenmode s = 2/r^2 of the Laplace-Beltrami operator, so the
Butterworth lowpass scales it by 1/(1 + (s/sc)^n), written here from the closed form, not from
the C++ core. Denoise logs the operator, the order and where its cutoff came from.
"""

import re
import unittest

import numpy as np

import geofilter_harness as h


def butterworth(s, sc, n):
    return 1.0 / (1.0 + (s / sc) ** n)


class DenoiseTest(unittest.TestCase):
    def run_steps(self, steps, tag):
        run, mesh = h.run_to_mesh(self, tag, steps)
        return run, mesh.vertices

    def test_butterworth_scales_a_sphere_by_the_closed_form(self):
        radius, sc = 0.5, 10.0
        for n in (2, 4, 8):
            with self.subTest(order=n):
                step = h.geofilter("GeoFilter: Butterworth Lowpass", cutoff=sc, order=n, useSelection=False)
                run, v = self.run_steps([h.sphere(radius, 3), step], f"n{n}")
                ratio = np.mean(h.radii(v)) / radius
                expected = butterworth(2 / radius ** 2, sc, n)
                self.assertAlmostEqual(ratio / expected, 1.0, delta=0.02, msg=f"n = {n}: ratio {ratio}, G = {expected}")
                self.assertTrue(any(f"Butterworth lowpass of order {n}" in l for l in run.log), run.describe())

    def test_denoise_with_a_selected_bump_cuts_at_twice_its_radius(self):
        # The selected cap stands for one bump: its measured radius r gives the cutoff 2/(2 r)^2.
        steps = [h.sphere(1.0, 4), h.select_faces("z0 > 0.95 && z1 > 0.95 && z2 > 0.95"),
                 h.geofilter("GeoFilter: Denoise", useSelection=True)]
        run, v = self.run_steps(steps, "selected")
        log = "\n".join(run.log)
        self.assertIn("selected bump", log, run.describe())
        self.assertIn("operator cotangent", log)
        # The cutoff the log reports is 2/(2 r)^2 of the measured radius r, and the sphere
        # (s = 2) is scaled by the 4th-order closed form at it.
        m = re.search(r"cutoff radius ([0-9.eE+-]+) = 2 x its radius ([0-9.eE+-]+)", log)
        self.assertIsNotNone(m, log)
        self.assertAlmostEqual(float(m.group(1)), 2 * float(m.group(2)), delta=1e-4 * float(m.group(1)))
        sc = float(re.search(r"cutoff sc = ([0-9.eE+-]+)", log).group(1))
        self.assertAlmostEqual(sc, 2 / float(m.group(1)) ** 2, delta=1e-4 * sc)
        self.assertAlmostEqual(np.mean(h.radii(v)) / butterworth(2.0, sc, 4), 1.0, delta=2e-3)

    def test_denoise_without_selection_picks_its_lowpass_by_its_estimated_risk(self):
        steps = [h.sphere(1.0, 4), h.geofilter("GeoFilter: Denoise", useSelection=False)]
        run, v = self.run_steps(steps, "none")
        log = "\n".join(run.log)
        m = re.search(r"risk estimate \(nothing selected\): ([0-9]+) of ([0-9]+) lowpasses scored", log)
        self.assertIsNotNone(m, run.describe())
        scored, candidates = int(m.group(1)), int(m.group(2))
        # Every candidate is listed, scored or not, the umbrella's seven cutoffs and the intrinsic
        # Delaunay's four; the downhill search skips at least one.
        listed = [line for line in run.log if re.search(r": {3}(per-vertex frequency|features of radius) ", line)]
        self.assertEqual(candidates, 11, log)
        self.assertEqual(len(listed), candidates, log)
        self.assertEqual(sum("not scored" not in line for line in listed), scored, log)
        self.assertLess(scored, candidates, log)
        chosen = [line for line in run.log if line.endswith("<- chosen")]
        self.assertEqual(len(chosen), 1, log)
        m = re.search(r"design: Butterworth lowpass of order 4, cutoff sc = ([0-9.eE+-]+), operator (umbrella|intrinsic Delaunay cotangent)", log)
        self.assertIsNotNone(m, log)
        self.assertIn(m.group(2), chosen[0])
        self.assertAlmostEqual(np.mean(h.radii(v)), 1.0, delta=2e-3)


if __name__ == "__main__":
    unittest.main()
