"""Every refusal: a non-zero exit, one line on stderr ("geofilter: error: ..."), nothing on
stdout, no output file, and the input (and any existing output) left byte for byte."""

import hashlib
import os
import unittest

import cli_harness as h


def snapshot(folder):
    """Every file of the folder (hidden ones too: a leftover temporary would show) with its hash."""
    out = {}
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            with open(path, "rb") as f:
                out[name] = hashlib.sha256(f.read()).hexdigest()
    return out


class ErrorTest(unittest.TestCase):
    def setUp(self):
        self.dir = h.workdir(self.id())
        v, f = h.icosphere(2, 1.0)
        self.input = os.path.join(self.dir, "in.ply")
        h.write_ply(self.input, v, f)
        # An older result that a refused run must not touch.
        self.existing = os.path.join(self.dir, "existing.off")
        h.write_off(self.existing, v, f)
        self.output = os.path.join(self.dir, "out.off")

    def assert_refused(self, *args, status=None, mentions=""):
        before = snapshot(self.dir)
        p = h.run(*args, cwd=self.dir)
        self.assertNotEqual(p.returncode, 0, h.describe(p))
        if status is not None:
            self.assertEqual(p.returncode, status, h.describe(p))
        lines = p.stderr.splitlines()
        self.assertEqual(len(lines), 1, h.describe(p))
        self.assertTrue(lines[0].startswith("geofilter: error: "), h.describe(p))
        self.assertIn(mentions, lines[0])
        self.assertEqual(p.stdout, "", h.describe(p))
        self.assertEqual(snapshot(self.dir), before, "a refused run changed, added or left files\n" + h.describe(p))
        return p

    def test_unknown_preset(self):
        self.assert_refused("smoothen", self.input, self.output, status=2, mentions="unknown preset 'smoothen'")

    def test_g1_equal_to_1(self):
        self.assert_refused("custom", "--G1", 1, self.input, self.output, status=1, mentions="G1")
        self.assert_refused("custom", "--G1", 1, self.input, self.existing, status=1, mentions="G1")

    def test_unstable_design(self):
        # docs/paper-notes.md §4: the printed highpass example has a real pole at s = 18.
        self.assert_refused("custom", "--s1", 25, "--s2", 10, "--G0", 1, "--G1", 3, "--Ginf", 0, self.input,
                            self.output, status=1, mentions="unstable")

    def test_unreadable_input(self):
        self.assert_refused("lowpass", os.path.join(self.dir, "missing.ply"), self.output, status=1, mentions="missing.ply")
        garbage = os.path.join(self.dir, "garbage.ply")
        with open(garbage, "w") as f:
            f.write("this is not a mesh\n")
        self.assert_refused("lowpass", garbage, self.output, status=1, mentions="garbage.ply")
        truncated = os.path.join(self.dir, "truncated.stl")
        with open(truncated, "wb") as f:
            f.write(b"\0" * 80 + b"\xff\xff\x00\x00")  # claims 65535 triangles, holds none
        self.assert_refused("lowpass", truncated, self.output, status=1, mentions="truncated.stl")
        self.assert_refused("lowpass", self.dir, self.output, status=1)
        self.assert_refused("lowpass", os.path.join(self.dir, "in.pcd"), self.output, status=1, mentions="format")

    def test_output_is_input(self):
        os.symlink("in.ply", os.path.join(self.dir, "link.ply"))
        os.link(self.input, os.path.join(self.dir, "hard.ply"))
        os.makedirs(os.path.join(self.dir, "sub"))
        for spelling in [self.input, "in.ply", "./in.ply", "sub/../in.ply", os.path.join(self.dir, "sub", "..", "in.ply"),
                         "link.ply", "hard.ply"]:
            with self.subTest(output=spelling):
                self.assert_refused("lowpass", "in.ply", spelling, status=1, mentions="--overwrite-input")

    def test_overwrite_input_when_asked(self):
        with open(self.input, "rb") as f:
            original = f.read()
        p = h.run("lowpass", "--overwrite-input", "./in.ply", "in.ply", cwd=self.dir)
        self.assertEqual(p.returncode, 0, h.describe(p))
        with open(self.input, "rb") as f:
            self.assertNotEqual(f.read(), original)
        self.assertEqual(len(h.read_mesh(self.input).vertices), 162)
        self.assertEqual(sorted(n for n in os.listdir(self.dir) if n.startswith(".")), [])

    def test_bad_command_lines(self):
        for args, mentions in [
            (["lowpass", "--s1", "abc"], "--s1 wants a number"),
            (["lowpass", "--s1", "nan"], "finite"),
            (["lowpass", "--bogus", "1"], "unknown option --bogus"),
            (["lowpass", "--zeros", "1"], "only to polezero"),
            (["lowpass", "--z1", "1"], "does not apply to the lowpass preset"),
            (["lowpass", "--solver", "magic"], "factored, pcg"),
            (["lowpass", "--s1", "1", "--s1", "2"], "given twice"),
            (["lowpass", "--radius", "-1"], "--radius must be a length >= 0"),
            (["lowpass", "--radius", "0.1", "--s1", "25"], "--radius and --s1 both give the feature's frequency"),
            (["lowpass", "--radius", "1", "--select-stored"], "use one of them"),
            (["lowpass", "--select-sphere", "1,2,3"], "cx,cy,cz,r"),
            (["polezero", "--zeros", "1,2,3,4,5"], "1 to 4 numbers"),
            (["lowpass", "--plot", "gain.svg"], ".png"),
            (["measure"], "measure needs the feature"),
        ]:
            with self.subTest(args=args):
                self.assert_refused(*args, self.input, self.output, status=2, mentions=mentions)
        self.assert_refused("lowpass", self.input, status=2, mentions="missing OUTPUT")
        self.assert_refused(status=2, mentions="no preset")

    def test_refusals_after_reading(self):
        self.assert_refused("lowpass", "--select-sphere", "5,5,5,0.1", self.input, self.output, status=1,
                            mentions="holds no face")
        self.assert_refused("lowpass", "--select-stored", self.input, self.output, status=1,
                            mentions="stores no face selection")
        self.assert_refused("polezero", "--radius", 1, "--feature-corner", "z3", self.input, self.output, status=1,
                            mentions="not in use")
        self.assert_refused("lowpass", self.input, os.path.join(self.dir, "no-such-dir", "out.off"), status=1,
                            mentions="no directory")
        # A NaN vertex is named by every filter, Denoise too (which measures the mesh first).
        v, f = h.icosphere(2, 1.0)
        v[7, 1] = float("nan")
        bad = os.path.join(self.dir, "nan.off")
        h.write_off(bad, v, f)
        for preset in ("lowpass", "butterworth", "denoise"):
            self.assert_refused(preset, bad, self.output, status=1, mentions="vertex 7 has a NaN or infinite coordinate")
        # Cannot converge in 2 iterations: the solver refuses, nothing is written.
        self.assert_refused("lowpass", "--s1", 25, "--solver", "pcg", "--max-iterations", 2, self.input, self.output, status=1)


if __name__ == "__main__":
    unittest.main()
