"""--plot draws G(s) into a PNG (gnuplot), for both design routes; a refused run draws nothing."""

import os
import struct
import unittest

import cli_harness as h

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != PNG_SIGNATURE:
        raise AssertionError(f"{path} is not a PNG")
    return struct.unpack(">II", head[16:24])


class PlotTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("plot")
        v, f = h.icosphere(2, 1.0)
        cls.input = os.path.join(cls.dir, "in.off")
        h.write_off(cls.input, v, f)

    def plot(self, name, *args):
        png = os.path.join(self.dir, name)
        p = h.run(*args, "--plot", png, self.input, os.path.join(self.dir, name + ".off"))
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertGreater(os.path.getsize(png), 1000)
        width, height = png_size(png)
        self.assertGreater(width, 300)
        self.assertGreater(height, 200)
        self.assertIn(f"and the plot {png}", p.stderr)
        return p

    def test_second_order_with_sign_change(self):
        # Fig. 1's parameters: G turns negative past s2 (docs/paper-notes.md §3), drawn dashed.
        p = self.plot("fig1.png", "custom", "--s1", 20, "--s2", 25, "--G0", 1, "--G1", 2, "--Ginf", 0)
        self.assertIn("changes sign", p.stderr)

    def test_pole_zero_with_feature(self):
        self.plot("polezero.png", "polezero", "--select-sphere", "0,0,0,1.5", "--feature-corner", "p1")

    def test_refused_run_draws_nothing(self):
        png = os.path.join(self.dir, "refused.png")
        p = h.run("custom", "--G1", 1, "--plot", png, self.input, os.path.join(self.dir, "refused.off"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertFalse(os.path.exists(png))


if __name__ == "__main__":
    unittest.main()
