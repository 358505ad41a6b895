"""geofilter-mpi reading, assembling and writing by slices, on a file made to cross every
boundary between the ranks' slices: two copies of the real mesh with their vertices
interleaved (every face spans slices, each component lives on every rank), the faces
shuffled, a vertex no face uses, a zero-area face, stale normals and a per-vertex quality.
Its output must equal geofilter's: the coordinates to 1e-7 of the diagonal, the recomputed
normals, the carried quality and the faces exactly. Files it cannot read by slices go to
rank 0 with the reason in the log; bad slices are refused with geofilter's messages."""

import os
import unittest

import numpy as np

import cli_harness
import mpi_harness

RANKS = 3
AGREEMENT = 1e-7  # of the bounding-box diagonal, at every vertex


def ply_columns(path):
    """The header and the vertex columns of a binary PLY written by geofilter or geofilter-mpi."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii")
    vertex_part = header.split("element vertex ")[1].split("element face")[0].splitlines()
    count = int(vertex_part[0])
    fields = [(l.split()[2], {"double": "<f8", "float": "<f4"}[l.split()[1]]) for l in vertex_part[1:]]
    columns = np.frombuffer(data, dtype=np.dtype(fields), count=count, offset=end)
    faces = data[end + columns.nbytes:]
    return header, columns, faces


class ReadBySlices(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = cli_harness.workdir("mpi_slices")
        mesh = cli_harness.read_mesh(mpi_harness.real_mesh())
        n = len(mesh.vertices)
        vertices = np.zeros((2 * n + 1, 3))
        vertices[0::2][:n] = mesh.vertices
        vertices[1::2][:n] = mesh.vertices + [1.5, 0.2, 0.0]
        vertices[-1] = [5.0, 5.0, 5.0]  # in no face
        faces = np.vstack([2 * mesh.faces, 2 * mesh.faces + 1, [[0, 0, 2]]])  # the last has no area
        faces = faces[np.random.default_rng(7).permutation(len(faces))]
        cls.vertices, cls.faces = vertices, faces
        cls.diagonal = float(np.linalg.norm(vertices[:-1].max(0) - vertices[:-1].min(0)))
        cls.input = os.path.join(cls.dir, "in_two_copies.ply")
        mpi_harness.write_binary_ply(cls.input, vertices, faces, double=True, normals=True,
                                     quality=np.arange(len(vertices)) % 97)

    def both(self, preset, *options, path=None, ranks=RANKS):
        path = path or self.input
        reference = os.path.join(self.dir, f"{preset}_reference.ply")
        distributed = os.path.join(self.dir, f"{preset}_np{ranks}.ply")
        single = cli_harness.run(preset, *options, path, reference, timeout=300)
        self.assertEqual(single.returncode, 0, cli_harness.describe(single))
        p = mpi_harness.run_mpi(ranks, preset, *options, path, distributed)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        return single, p, reference, distributed

    def test_output_equals_geofilters(self):
        # highpass: G0 != 1 scales each component about its own centroid, which the ranks
        # must agree on; lowpass and notch: an exact pair each; butterworth: CG pairs sharing
        # one real factor.
        for preset in ("highpass", "lowpass", "notch", "butterworth"):
            with self.subTest(preset=preset):
                single, p, reference, distributed = self.both(preset)
                self.assertTrue(mpi_harness.read_by_slices(p), p.stderr)
                self.assertIn("in 2 component(s)", p.stderr)
                self.assertIn("1 zero-area face(s) skipped", p.stderr)
                self.assertIn("1 vertex/vertices belong to no usable face", p.stderr)
                expected_header, expected, expected_faces = ply_columns(reference)
                header, got, faces = ply_columns(distributed)
                self.assertEqual(header.replace("geofilter-mpi", "geofilter"), expected_header)
                self.assertEqual(faces, expected_faces, "the faces differ")
                xyz = lambda c: np.column_stack([c["x"], c["y"], c["z"]])
                moved = np.abs(xyz(expected) - self.vertices).max()
                self.assertGreater(moved, 1e3 * AGREEMENT * self.diagonal)
                worst = np.abs(xyz(got) - xyz(expected)).max() / self.diagonal
                self.assertLess(worst, AGREEMENT, f"{preset}: differs from geofilter by {worst:.3g} of the diagonal")
                self.assertTrue(np.array_equal(xyz(got)[-1], [5.0, 5.0, 5.0]), "the vertex in no face moved")
                normals = lambda c: np.column_stack([c["nx"], c["ny"], c["nz"]]).astype(float)
                self.assertLess(np.abs(normals(got) - normals(expected)).max(), 1e-5)
                self.assertGreater(np.abs(normals(expected)).max(), 0.5, "the normals were not recomputed")
                self.assertTrue(np.array_equal(got["quality"], expected["quality"]))

    def test_selected_feature_is_measured_across_ranks(self):
        ear = self.vertices[np.argmax(self.vertices[:-1, 1])]
        select = ["--select-sphere", ",".join(f"{c:.6f}" for c in ear) + ",0.06"]
        single, p, reference, distributed = self.both("exaggerate", *select)
        self.assertTrue(mpi_harness.read_by_slices(p), p.stderr)
        feature = [l for l in single.stderr.splitlines() if l.startswith("geofilter: feature:")]
        self.assertEqual(len(feature), 1, single.stderr)
        self.assertIn("geofilter-mpi" + feature[0][len("geofilter"):], p.stderr.splitlines())
        worst = np.abs(cli_harness.read_mesh(distributed).vertices - cli_harness.read_mesh(reference).vertices).max()
        self.assertLess(worst / self.diagonal, AGREEMENT)

    def test_one_rank_reads_by_slices_too(self):
        single, p, reference, distributed = self.both("lowpass", ranks=1)
        self.assertTrue(mpi_harness.read_by_slices(p), p.stderr)
        worst = np.abs(cli_harness.read_mesh(distributed).vertices - cli_harness.read_mesh(reference).vertices).max()
        self.assertLess(worst / self.diagonal, AGREEMENT)

    def test_polygons_go_to_rank_0_and_say_why(self):
        path = os.path.join(self.dir, "in_with_a_quad.ply")
        mesh = cli_harness.read_mesh(mpi_harness.real_mesh())
        n = len(mesh.vertices)
        quad_corners = np.vstack([mesh.vertices, mesh.vertices[:4] + [0, 0, 3.0]])
        mpi_harness.write_binary_ply(path, quad_corners, mesh.faces, polygons=[[n, n + 1, n + 2, n + 3]])
        p = mpi_harness.run_mpi(RANKS, "lowpass", path, os.path.join(self.dir, "quad_out.ply"))
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        self.assertFalse(mpi_harness.read_by_slices(p))
        self.assertIn("rank 0 reads the whole mesh: the file's size is not that of triangles only", p.stderr)


class BadSlices(unittest.TestCase):
    """Refusals found by one rank in its slice: one line, geofilter's message, no output."""

    def setUp(self):
        self.dir = cli_harness.workdir(self.id())
        self.output = os.path.join(self.dir, "out.ply")
        mesh = cli_harness.read_mesh(mpi_harness.real_mesh())
        self.vertices, self.faces = mesh.vertices.copy(), mesh.faces.copy()

    def refused(self, expect):
        path = os.path.join(self.dir, "in.ply")
        mpi_harness.write_binary_ply(path, self.vertices, self.faces)
        before = open(path, "rb").read()
        single = cli_harness.run("lowpass", path, self.output)
        p = mpi_harness.run_mpi(RANKS, "lowpass", path, self.output, timeout=120)
        self.assertEqual(p.returncode, 1, cli_harness.describe(p))
        errors = mpi_harness.error_lines(p)
        self.assertEqual(len(errors), 1, cli_harness.describe(p))
        self.assertIn(expect, errors[0])
        self.assertEqual(errors[0][len("geofilter-mpi"):], single.stderr.strip().splitlines()[-1][len("geofilter"):])
        self.assertFalse(os.path.exists(self.output), "an output file was written")
        self.assertEqual(sorted(os.listdir(self.dir)), ["in.ply"], "files left behind")
        self.assertEqual(open(path, "rb").read(), before, "the input was changed")

    def test_nan_in_the_last_ranks_slice(self):
        self.vertices[len(self.vertices) - 10, 1] = np.nan
        self.refused(f"vertex {len(self.vertices) - 10} has a NaN")

    def test_corner_out_of_range_in_the_middle_slice(self):
        self.faces[len(self.faces) // 2, 2] = 10 ** 7
        self.refused(f"face {len(self.faces) // 2} uses vertex 10000000")

    def test_every_face_without_area(self):
        self.vertices[:, 2] = 0
        self.vertices[:, 1] = 0
        self.refused("every face of the mesh has zero area")


if __name__ == "__main__":
    unittest.main()
