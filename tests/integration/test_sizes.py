"""The dialog in sizes, through meshlabserver 2020.09: a script that gives only the feature
radius (an absolute length, as MeshLab stores a RichAbsPerc) filters exactly as geofilter's
--radius does, and a script written before the radius existed (it sets s1 and s2 and omits
the radius, the first parameter) filters exactly as the same frequencies typed on geofilter.
"""

import os
import subprocess
import unittest

import numpy as np

import geofilter_harness as h
import shapes


def cli():
    path = os.environ.get("GEOFILTER_CLI", "")
    if not os.access(path, os.X_OK):
        raise AssertionError(f"no geofilter tool at '{path}' (GEOFILTER_CLI, set by ctest)")
    return path


class SizesMatchTheCommandLine(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir_for(cls.__module__)
        # A lumpy sphere, so that every filter moves every vertex by a different amount.
        v, f = shapes.icosphere(3, 1.0)
        v = np.asarray(v, dtype=float)
        lumps = 1 + 0.05 * np.sin(7 * v[:, 0]) * np.cos(5 * v[:, 1])
        cls.input = os.path.join(cls.dir, "lumpy.ply")
        h.write_ply_ascii(cls.input, h.PlyMesh(v * lumps[:, None], np.asarray(f)))
        cls.mesh = h.read_ply(cls.input)   # as MeshLab reads it: floats
        cls.diagonal = float(np.linalg.norm(cls.mesh.vertices.max(axis=0) - cls.mesh.vertices.min(axis=0)))

    def meshlab(self, tag, step):
        out = os.path.join(self.dir, tag + ".ply")
        run = h.run_meshlabserver(self.dir, [step], inputs=[self.input], outputs=[(out, None)], script_name=tag + ".mlx")
        self.assertEqual(run.returncode, 0, run.describe())
        return run, h.read_ply(out).vertices

    def geofilter(self, tag, *args):
        out = os.path.join(self.dir, tag + "-cli.ply")
        p = subprocess.run([cli(), *map(str, args), "--tolerance", "1e-10", self.input, out], capture_output=True,
                           text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        return h.read_ply(out).vertices

    def assert_same(self, a, b, what):
        worst = float(np.abs(a - b).max())
        self.assertLess(worst, 1e-6 * self.diagonal, f"{what}: {worst / self.diagonal:.3g} of the diagonal apart")

    def test_a_radius_alone_gives_the_command_lines_radius(self):
        cases = [("GeoFilter: Lowpass", "lowpass", 0.15), ("GeoFilter: Band Exaggeration", "exaggerate", 0.2),
                 ("GeoFilter: Butterworth Lowpass", "butterworth", 0.3)]
        for name, preset, r in cases:
            with self.subTest(preset=preset):
                run, meshlab = self.meshlab(preset + "-radius", h.geofilter(name, radius=r))
                self.assertTrue(any(f"from the feature radius r = {r:g}" in line for line in run.log), run.describe())
                self.assert_same(meshlab, self.geofilter(preset + "-radius", preset, "--radius", r), preset)
                moved = float(np.abs(meshlab - self.mesh.vertices).max())
                self.assertGreater(moved, 1e-3 * self.diagonal, "the filter changed the mesh")

    def test_the_default_radius_is_the_same_fraction_of_the_diagonal_everywhere(self):
        run, meshlab = self.meshlab("lowpass-default", h.geofilter("GeoFilter: Lowpass"))
        fraction = next(p for p in h.FILTERS["GeoFilter: Lowpass"] if p.name == "radius")
        self.assertEqual(fraction.rich_type, "RichAbsPerc")
        self.assert_same(meshlab, self.geofilter("lowpass-default", "lowpass"), "the default radius")

    def test_an_older_script_with_s1_and_s2_runs_as_before(self):
        # Every parameter an older version had, none of the radius: meshlabserver fills in the
        # radius alone, and the typed frequencies win over it.
        older = h.Step("GeoFilter: Notch", [(p, {"s1": 180.0, "s2": 400.0}.get(p.name, p.default))
                                            for p in h.FILTERS["GeoFilter: Notch"] if p.name != "radius"])
        run, meshlab = self.meshlab("notch-older", older)
        self.assertTrue(any("s1 = 180, s2 = 400 as typed" in line for line in run.log), run.describe())
        self.assert_same(meshlab, self.geofilter("notch-older", "notch", "--s1", 180, "--s2", 400), "typed s1, s2")


if __name__ == "__main__":
    unittest.main()
