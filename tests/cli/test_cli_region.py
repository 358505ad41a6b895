"""--region and --blend-width through the command-line tool: only the selection and
its band move, the rest is written back bit for bit; the PLY vertex quality as a weight."""

import os
import unittest

import numpy as np

import cli_harness as h


def write_ply_quality(path, v, f, q):
    with open(path, "w") as out:
        out.write("ply\nformat ascii 1.0\n")
        out.write(f"element vertex {len(v)}\nproperty double x\nproperty double y\nproperty double z\n"
                  "property float quality\n")
        out.write(f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
        out.writelines("%.17g %.17g %.17g %.9g\n" % (p[0], p[1], p[2], w) for p, w in zip(v, q))
        out.writelines("3 %d %d %d\n" % tuple(t) for t in f)


class Region(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("region")
        cls.v, cls.f = h.icosphere(3, 1.0)
        cls.source = os.path.join(cls.dir, "sphere.ply")
        h.write_ply(cls.source, cls.v, cls.f)

    def out(self, name):
        return os.path.join(self.dir, name)

    def test_selected_region_moves_only_the_cap_and_its_band(self):
        p = h.run("exaggerate", "--region", "selected", "--select-sphere", "0,0,1,0.5", "--blend-width", "0.3",
                  "--s1", 20, self.source, self.out("cap.ply"))
        self.assertEqual(p.returncode, 0, h.describe(p))
        v = h.read_mesh(self.out("cap.ply")).vertices
        moved = np.linalg.norm(v - self.v, axis=1) > 0
        self.assertTrue(moved.any())
        # The ball reaches z = 0.875 on the sphere; the band adds at most 0.3 along the surface.
        self.assertTrue(np.all(self.v[moved, 2] > 0.875 - 0.31), "a vertex beyond the band moved")
        far = self.v[:, 2] < 0.5
        np.testing.assert_array_equal(v[far], self.v[far])
        self.assertIn("left exactly as they were", p.stderr)
        self.assertIn("s1 as typed", p.stderr, "--s1 with --region selected: the frequency is typed")

    def test_selection_gives_frequency_and_region(self):
        p = h.run("exaggerate", "--region", "selected", "--select-sphere", "0,0,1,0.5", self.source, self.out("same.ply"))
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertRegex(p.stderr, r"s1 = \S+ from \d+ selected faces")
        self.assertIn("auto: the feature radius", p.stderr)

    def test_quality_weight(self):
        whole = self.out("whole.ply")
        self.assertEqual(h.run("lowpass", self.source, whole).returncode, 0)
        for name, q in [("one", np.ones(len(self.v))), ("big", np.full(len(self.v), 1.5)), ("zero", np.zeros(len(self.v)))]:
            with self.subTest(weight=name):
                src = self.out(f"q-{name}.ply")
                write_ply_quality(src, self.v, self.f, q)
                p = h.run("lowpass", "--region", "quality", src, self.out(f"out-{name}.ply"))
                self.assertEqual(p.returncode, 0, h.describe(p))
                got = h.read_mesh(self.out(f"out-{name}.ply")).vertices
                expected = self.v if name == "zero" else h.read_mesh(whole).vertices
                np.testing.assert_array_equal(got, expected)
                if name == "big":
                    self.assertIn("clamped", p.stderr)

    def test_denoise_on_a_selected_region_denoises_it_and_leaves_the_rest(self):
        # A noisy sphere: Denoise on the selected cap removes the noise there (the selection is
        # the region, not a bump to flatten) and writes everything beyond the band back as it was.
        v, f = h.icosphere(4, 1.0)
        v, f = np.asarray(v, dtype=float), np.asarray(f)
        edge = np.mean(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1))
        rng = np.random.default_rng(11)
        noisy = v * (1 + 0.3 * edge * rng.standard_normal(len(v)))[:, None]
        src = self.out("noisy.ply")
        h.write_ply(src, noisy, f)
        p = h.run("denoise", "--region", "selected", "--select-sphere", "0,0,1,0.6", "--blend-width", "0.2", src,
                  self.out("denoised-cap.ply"), timeout=300)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("sampling-noise rule", p.stderr)
        got = h.read_mesh(self.out("denoised-cap.ply")).vertices
        off = lambda p: np.abs(np.linalg.norm(p, axis=1) - 1)
        # The selected faces lie in the ball of radius 0.6 around the pole: well inside it, every
        # vertex is in the region.
        inside = np.linalg.norm(noisy - [0, 0, 1], axis=1) < 0.5
        self.assertGreater(inside.sum(), 20)
        self.assertLess(np.sqrt(np.mean(off(got[inside]) ** 2)), 0.7 * np.sqrt(np.mean(off(noisy[inside]) ** 2)))
        # The ball reaches z = 0.82 on the sphere; the band adds at most 0.2 along the surface.
        far = noisy[:, 2] < 0.5
        self.assertGreater(far.sum(), len(v) // 2)
        np.testing.assert_array_equal(got[far], noisy[far])

    def test_refusals(self):
        p = h.run("lowpass", "--region", "selected", self.source, self.out("no.ply"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("--select-sphere", p.stderr)
        p = h.run("lowpass", "--region", "quality", self.source, self.out("noq.ply"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("quality", p.stderr)
        nan = self.out("nan.ply")
        q = np.ones(len(self.v))
        q[4] = np.nan
        write_ply_quality(nan, self.v, self.f, q)
        p = h.run("lowpass", "--region", "quality", nan, self.out("nanout.ply"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("NaN", p.stderr)
        self.assertFalse(os.path.exists(self.out("nanout.ply")))


if __name__ == "__main__":
    unittest.main()
