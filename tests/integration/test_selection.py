"""(c) The frequency taken from a selection made in the same meshlabserver script.

Whole sphere of radius R selected with Conditional Face Selection: the fitted ellipsoid's
radius is R, so the Lowpass must log "s1 = 2/R^2 from N selected faces" (sphere-like).
"""

import re
import unittest

import numpy as np

import geofilter_harness as h

ALL_FACES = "(fi >= 0)"


def logged_s1(run):
    for line in run.log:
        m = re.search(r": s1 = ([0-9.eE+-]+) from \d+ selected faces", line)
        if m:
            return float(m.group(1))
    return None


class FrequencyFromSelection(unittest.TestCase):
    def run_steps(self, tag, steps):
        return h.run_to_mesh(self, tag, steps)

    def test_whole_sphere_gives_2_over_R2(self):
        for radius in (0.5, 2.0):
            with self.subTest(radius=radius):
                run, out = self.run_steps(f"R{radius}", [
                    h.sphere(radius, 3), h.select_faces(ALL_FACES),
                    # s1, s2 as given only fix the ratio s2/s1 = 2 (the 40 dB/decade lowpass).
                    h.geofilter("GeoFilter: Lowpass", useSelection=True, s1=25, s2=50)])
                s1 = logged_s1(run)
                self.assertIsNotNone(s1, run.describe())
                self.assertAlmostEqual(s1 / (2 / radius ** 2), 1.0, delta=0.05, msg=f"s1 = {s1}")
                # That design puts the sphere itself on the peak: G(s1) = G1 = 1.1.
                ratio = np.mean(h.radii(out.vertices)) / radius
                expected = h.eq15_gain(2 / radius ** 2, s1, 2 * s1, 1.0, 1.1, 0.0)
                self.assertAlmostEqual(ratio, expected, delta=0.02)

    def test_cylinder_like_shape_halves_the_frequency(self):
        radius = 0.5
        run, _ = self.run_steps("cyl", [
            h.sphere(radius, 3), h.select_faces(ALL_FACES),
            h.geofilter("GeoFilter: Lowpass", useSelection=True, featureShape=1)])
        s1 = logged_s1(run)
        self.assertIsNotNone(s1, run.describe())
        self.assertAlmostEqual(s1 / (1 / radius ** 2), 1.0, delta=0.05, msg=f"s1 = {s1}")

    def test_pole_zero_corner_follows_the_selection(self):
        radius = 0.5
        run, _ = self.run_steps("pz", [
            h.sphere(radius, 3), h.select_faces(ALL_FACES),
            h.geofilter("GeoFilter: Pole-Zero", useSelection=True, featureCorner=4)])  # p1
        m = [re.search(r"corner p1 = ([0-9.eE+-]+) from \d+ selected faces", l) for l in run.log]
        m = [x for x in m if x]
        self.assertTrue(m, run.describe())
        self.assertAlmostEqual(float(m[0].group(1)) / (2 / radius ** 2), 1.0, delta=0.05)


if __name__ == "__main__":
    unittest.main()
