"""PLY, OBJ, OFF and STL in and out through the tool's readers and writers, and PLY's stored face selection.

STL stores every triangle with its own three corners: the tool welds bit-identical corners
on reading (the filter needs a connected mesh) and writes three corners per triangle again.
"""

import os
import unittest

import numpy as np

import cli_harness as h

FORMATS = ["ply", "obj", "off", "stl"]
SELECTED = 0x20  # vcglib's face flag bit for "selected", as MeshLab stores it


def unique_rows(points, decimals=6):
    return np.unique(np.round(points, decimals), axis=0)


class FormatTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("formats")
        cls.v, cls.f = h.icosphere(3, 0.5)
        # The reference result: OFF in, OFF out (full precision).
        cls.reference_in = os.path.join(cls.dir, "reference.off")
        h.write_off(cls.reference_in, cls.v, cls.f)
        cls.reference_out = os.path.join(cls.dir, "reference-out.off")
        p = h.run("exaggerate", "--radius", 0.5, cls.reference_in, cls.reference_out)
        assert p.returncode == 0, h.describe(p)
        cls.expected = h.read_mesh(cls.reference_out).vertices

    def test_round_trip_each_format(self):
        for ext in FORMATS:
            with self.subTest(format=ext):
                source = os.path.join(self.dir, f"sphere.{ext}")
                h.WRITERS[ext](source, self.v, self.f)
                out = os.path.join(self.dir, f"out.{ext}")
                p = h.run("exaggerate", "--radius", 0.5, source, out)
                self.assertEqual(p.returncode, 0, h.describe(p))
                self.assertIn(f"read {source}: {len(self.v)} vertices, {len(self.f)} triangles", p.stderr)
                m = h.read_mesh(out)
                self.assertEqual(len(m.faces), len(self.f))
                if ext == "stl":
                    self.assertIn(f"welded its {3 * len(self.f)} triangle corners into {len(self.v)} vertices", p.stderr)
                    self.assertEqual(len(m.vertices), 3 * len(self.f))  # as STL stores them
                    got = unique_rows(m.vertices, 5)
                    self.assertEqual(len(got), len(self.v))
                    np.testing.assert_allclose(got, unique_rows(self.expected, 5), atol=2e-5)
                else:
                    self.assertEqual(len(m.vertices), len(self.v))
                    # OBJ and OFF are written with 17 significant digits, PLY in double.
                    np.testing.assert_allclose(m.vertices, self.expected, atol=2e-6 if ext == "obj" else 1e-12)

    def test_obj_faces_around_the_first_vertex_and_polygons(self):
        # A cube: quads (triangulated on reading), v/vt/vn and v//vn corners, relative indices,
        # and vertex 1 in three faces (the 2020.09 vcglib the tool once used dropped those: MeshLab issue #791).
        source = os.path.join(self.dir, "cube.obj")
        with open(source, "w") as f:
            f.write("# cube\n")
            for x in (-1, 1):
                for y in (-1, 1):
                    for z in (-1, 1):
                        f.write(f"v {x} {y} {z}\n")
            f.write("vt 0 0\nvn 0 0 1\n")
            f.write("f 1 2 4 3\nf 5/1/1 7/1/1 8/1/1 6/1/1\nf 1//1 5//1 6//1 2//1\n"
                    "f -5 -1 -2 -6\nf 1 3 7 5\nf 2 6 8 4\n")
        out = os.path.join(self.dir, "cube-out.off")
        p = h.run("lowpass", "--s1", 2, "--s2", 4, source, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("8 vertices, 12 triangles (OBJ)", p.stderr)
        m = h.read_off(out)
        self.assertEqual((len(m.vertices), len(m.faces)), (8, 12))
        self.assertEqual(len(np.unique(m.faces)), 8)

    def test_cross_format_and_case_insensitive_extension(self):
        source = os.path.join(self.dir, "cross.stl")
        h.write_stl(source, self.v, self.f)
        out = os.path.join(self.dir, "cross-out.PLY")
        p = h.run("exaggerate", "--radius", 0.5, source, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        m = h.read_ply(out)
        self.assertEqual(len(m.vertices), len(self.v))  # welded once, written shared
        np.testing.assert_allclose(unique_rows(m.vertices, 5), unique_rows(self.expected, 5), atol=2e-5)

    def test_stored_selection(self):
        # The faces --select-box picks below: all three vertices at z >= 0.35.
        cap = np.all(self.v[self.f][:, :, 2] >= 0.35, axis=1)
        # Other bits (here a border bit, 0x40) must not reach the output or count as selection.
        flags = np.where(cap, SELECTED | 0x40, 0x40)
        source = os.path.join(self.dir, "stored.ply")
        h.write_ply(source, self.v, self.f, flags)
        out = os.path.join(self.dir, "stored-out.ply")
        p = h.run("lowpass", "--select-stored", source, out)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn(f"stored face flags: {cap.sum()} of {len(self.f)} faces selected", p.stderr)
        m = h.read_ply(out)
        self.assertIsNotNone(m.face_flags, "the output PLY lost the selection")
        np.testing.assert_array_equal(m.face_flags, np.where(cap, SELECTED, 0))

        # The same faces picked by a region measure the same feature.
        stored = h.run("measure", "--select-stored", source)
        region = h.run("measure", "--select-box", "-1,-1,0.35,1,1,1", self.reference_in)
        self.assertEqual(stored.returncode, 0, h.describe(stored))
        self.assertEqual(region.returncode, 0, h.describe(region))
        self.assertEqual(stored.stdout.splitlines()[-1], region.stdout.splitlines()[-1])

        # Not asked for, the stored selection is only mentioned.
        p = h.run("lowpass", source, os.path.join(self.dir, "ignored.off"))
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("--select-stored would take the feature from it", p.stderr)
        self.assertIn("from the feature radius", p.stderr)


if __name__ == "__main__":
    unittest.main()
