"""Every preset of the filter table runs from the command line; the options generated from
the table reach the filter; --help and --quiet behave."""

import os
import unittest

import numpy as np

import cli_harness as h
import filter_table

# The second-order and pole-zero presets, as the build's filter table lists them.
FILTER_PRESETS = [f["cli_name"] for f in filter_table.by_kind("SecondOrder", "PoleZero")]


class PresetTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("presets")
        cls.v, cls.f = h.icosphere(3, 0.5)
        cls.off = os.path.join(cls.dir, "sphere.off")
        cls.ply = os.path.join(cls.dir, "sphere.ply")
        h.write_off(cls.off, cls.v, cls.f)
        h.write_ply(cls.ply, cls.v, cls.f)

    def test_every_filter_preset_runs(self):
        for preset in FILTER_PRESETS:
            for source in (self.off, self.ply):
                with self.subTest(preset=preset, source=os.path.basename(source)):
                    out = os.path.join(self.dir, f"{preset}-{os.path.basename(source)}")
                    p = h.run(preset, source, out)
                    self.assertEqual(p.returncode, 0, h.describe(p))
                    m = h.read_mesh(out)
                    self.assertEqual(len(m.vertices), len(self.v))
                    self.assertEqual(len(m.faces), len(self.f))
                    self.assertTrue(np.all(np.isfinite(m.vertices)))
                    # One summary line on stdout naming the preset; the log on stderr.
                    self.assertEqual(len(p.stdout.splitlines()), 1, h.describe(p))
                    self.assertTrue(p.stdout.startswith(f"geofilter: {preset}: "), h.describe(p))
                    self.assertTrue(any(l.startswith("solver ") for l in h.log_lines(p)), h.describe(p))

    def test_measure_prints_the_feature(self):
        p = h.run("measure", "--select-sphere", "0,0,0,0.6", self.off)
        self.assertEqual(p.returncode, 0, h.describe(p))
        s = float(p.stdout.split("sphere-like s = 2/r^2 = ")[1].split(",")[0])
        self.assertAlmostEqual(s, 2 / 0.5 ** 2, delta=0.05 * 8)
        ellipsoid = os.path.join(self.dir, "ellipsoid.ply")
        p = h.run("measure", "--select-sphere", "0,0,0,0.6", self.off, ellipsoid)
        self.assertEqual(p.returncode, 0, h.describe(p))
        r = h.radii(h.read_mesh(ellipsoid).vertices)
        self.assertAlmostEqual(float(np.mean(r)), 0.5, delta=0.02)

    def test_table_options_reach_the_filter(self):
        out = os.path.join(self.dir, "options.off")
        p = h.run("custom", "--s1", 40, "--s2", 90, "--G0", 0.9, "--G1", 1.5, "--Ginf", 0.5, "--solver", "pcg",
                  "--tolerance", "1e-9", "--max-iterations", 5000, self.off, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("design: s1 = 40, s2 = 90, G0 = 0.9, G1 = 1.5, Ginf = 0.5", p.stderr)
        self.assertIn("Jacobi-PCG", p.stderr)
        # Options by the table's own names, and enum choices by any unambiguous word or index.
        capped = os.path.join(self.dir, "capped.off")
        p = h.run("custom", "--maxIterations=3", "--solver=jacobi", self.off, capped)
        self.assertEqual(p.returncode, 1, h.describe(p))  # 3 iterations cannot converge
        self.assertFalse(os.path.exists(capped))
        p = h.run("custom", "--solver", "1", "--feature-shape", "cylinder", "--radius", 0.5, self.off, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertAlmostEqual(h.log_value(p, r"design: s1 = ([-+.\deE]+)"), 1 / 0.5 ** 2, places=4)

    def test_bool_parameter_forms(self):
        # fixBoundary, a yes/no table parameter: --fix-boundary, --fix-boundary=no, --no-fix-boundary.
        keep = ~np.all(self.v[self.f][:, :, 2] > 0.3, axis=1)  # a hole around the north pole
        faces = self.f[keep]
        source = os.path.join(self.dir, "open.ply")
        h.write_ply(source, self.v, faces)
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
        unique, counts = np.unique(edges, axis=0, return_counts=True)
        rim = np.unique(unique[counts == 1])
        self.assertGreater(len(rim), 0)
        moved = {}
        for args in (["--fix-boundary"], ["--fix-boundary=yes"], ["--fix-boundary=no"], ["--no-fix-boundary"], []):
            out = os.path.join(self.dir, "open-out.ply")
            p = h.run("lowpass", *args, source, out)
            self.assertEqual(p.returncode, 0, h.describe(p))
            v = h.read_ply(out).vertices
            moved[" ".join(args)] = float(np.max(np.abs(v[rim] - self.v[rim])))
        self.assertLess(moved["--fix-boundary"], 1e-9, moved)
        self.assertLess(moved["--fix-boundary=yes"], 1e-9, moved)
        for free in ("--fix-boundary=no", "--no-fix-boundary", ""):
            self.assertGreater(moved[free], 1e-4, moved)
        p = h.run("lowpass", "--fix-boundary=maybe", source, os.path.join(self.dir, "x.ply"))
        self.assertEqual(p.returncode, 2, h.describe(p))

    def test_polezero_lists(self):
        out = os.path.join(self.dir, "pz.off")
        p = h.run("polezero", "--zeros", "30", "--poles", "10,90", "--G0", 1, self.off, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("zeros 30, poles 10, 90", p.stdout)
        # The list replaces all four corners: z2 (400 by default) is unused now.
        self.assertNotIn("400", p.stdout)
        p = h.run("polezero", "--zeros", "30", "--z2", "40", self.off, out)
        self.assertEqual(p.returncode, 2, h.describe(p))

    def test_help(self):
        p = h.run("--help")
        self.assertEqual(p.returncode, 0, h.describe(p))
        for preset in FILTER_PRESETS + ["measure"]:
            self.assertIn(f"\n  {preset} ", p.stdout)
        self.assertIn("examples:", p.stdout)
        p = h.run("lowpass", "--help")
        self.assertEqual(p.returncode, 0, h.describe(p))
        for option in ["--s1", "--s2", "--G0", "--G1", "--Ginf", "--feature-shape sphere|cylinder",
                       "--fix-boundary, --no-fix-boundary", "--solver factored|pcg", "--tolerance", "--max-iterations"]:
            self.assertIn(option, p.stdout)
        p = h.run("polezero", "--help")
        for option in ["--z1", "--z4", "--p1", "--p4", "--feature-corner z1|z2|z3|z4|p1|p2|p3|p4", "--zeros"]:
            self.assertIn(option, p.stdout)

    def test_quiet(self):
        out = os.path.join(self.dir, "quiet.off")
        p = h.run("lowpass", "--quiet", self.off, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertEqual(p.stdout + p.stderr, "")
        self.assertEqual(len(h.read_mesh(out).vertices), len(self.v))


if __name__ == "__main__":
    unittest.main()
