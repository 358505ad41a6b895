"""A point cloud layer (vertices, no faces) filtered through meshlabserver 2020.09: the plugin
builds the cloud's Laplacian, so a noisy sphere of points is smoothed like the sphere mesh,
and its mean radius scales by the designed gain at the sphere's frequency 2/r^2 (section 5's
sphere test, on points)."""

import os
import unittest

import numpy as np

import geofilter_harness as h
from shapes import fibonacci_sphere


class CloudLayer(unittest.TestCase):
    def test_a_noisy_sphere_cloud_is_lowpassed_like_the_sphere(self):
        d = h.workdir_for(self.id())
        rng = np.random.default_rng(1)
        noisy = fibonacci_sphere(3000, 1.0) * (1 + 0.01 * rng.standard_normal((3000, 1)))
        source, out = os.path.join(d, "cloud.ply"), os.path.join(d, "out.ply")
        h.write_ply_ascii(source, h.PlyMesh(noisy, np.zeros((0, 3), dtype=int)))
        r = 0.3
        run = h.run_meshlabserver(d, [h.geofilter("GeoFilter: Lowpass", radius=r)], inputs=[source],
                                  outputs=[(out, None)])
        self.assertEqual(run.returncode, 0, run.describe())
        self.assertTrue(any("point cloud: 3000 points" in line for line in run.log), run.describe())
        filtered = h.read_ply(out).vertices
        self.assertEqual(filtered.shape, noisy.shape)
        radii_before, radii_after = np.linalg.norm(noisy, axis=1), np.linalg.norm(filtered, axis=1)
        self.assertLess(np.std(radii_after), 0.3 * np.std(radii_before), "the noise must mostly go")
        s1 = 2 / r ** 2
        expected = abs(h.eq15_gain(2.0, s1, 2 * s1, 1.0, 1.1, 0.0))
        self.assertAlmostEqual(np.mean(radii_after) / np.mean(radii_before), expected, delta=0.01 * expected)


if __name__ == "__main__":
    unittest.main()
