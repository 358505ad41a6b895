"""geofilter-mpi on N ranks gives geofilter's coordinates on a real mesh for every preset of
the filter table (and the feature, operator and boundary options that reach the solver),
to 1e-7 of the bounding-box diagonal. N comes from $GEOFILTER_MPI_RANKS (one ctest per N).
The mesh is a binary PLY, so that the presets on the cotangent Laplacian of the whole mesh
take the path that reads, assembles and writes by slices, and the others (Denoise, the
fixed boundary, another operator) the path where rank 0 reads the mesh.

geofilter's results (the reference) are computed once for every rank count: `--references`
writes them (ctest's mpi.references, a fixture of each mpi.presets.npN) and the tests read them."""

import json
import os
import re
import shutil
import sys
import unittest

import numpy as np

import cli_harness
import filter_table
import mpi_harness
import shapes
from shapes import fibonacci_sphere

RANKS = int(os.environ.get("GEOFILTER_MPI_RANKS", "2"))
AGREEMENT = 1e-7  # of the bounding-box diagonal, at every vertex
DENOISE_RANKS = 2  # the rank count that runs Denoise with nothing selected
BUMP_RADIUS = 0.15
NOISE = 0.3  # Denoise's noisy sphere: Gaussian noise of this many mean edge lengths along the normals


def references_dir():
    return os.path.join(os.environ.get("GEOFILTER_TEST_WORKDIR") or "/tmp", "mpi_presets_references")


def slug(name):
    return re.sub(r"[^A-Za-z0-9]+", "_", name)


def feature_selection(vertices):
    """A ball of radius 0.06 about the bunny's highest vertex (the tip of an ear)."""
    top = vertices[np.argmax(vertices[:, 1])]
    return ["--select-sphere", ",".join(f"{c:.6f}" for c in top) + ",0.06"]


def reads_by_slices(preset, options):
    """Which runs geofilter-mpi should read by slices."""
    return preset != "denoise" and "--fix-boundary" not in options and "--operator" not in options


def cases(vertices, ranks=RANKS):
    """(name, preset, options): every filter of the table at its defaults, then the options
    that change what the distributed solver is given."""
    out = [(f["cli_name"], f["cli_name"], []) for f in filter_table.TABLE if f["kind"] != "Measure"]
    assert len(out) >= 9, "the filter table lost its presets"
    assert any(case[1] == "denoise" for case in out), "the filter table lost Denoise"
    # Denoise with nothing selected runs a whole filter per candidate cutoff through the
    # distributed solver (90 s on this mesh at two ranks on two cores): it runs on a smaller
    # noisy sphere instead, at two ranks (test_denoise_of_sampling_noise_matches_geofilter).
    # Every rank count runs Denoise of a selected bump (below), which takes the same rank-0
    # path, and every preset's distributed solve.
    out = [case for case in out if case[1] != "denoise"]
    ear = feature_selection(vertices)
    out += [
        ("exaggerate from a selected feature", "exaggerate", ear),
        ("lowpass with the boundary fixed", "lowpass", ["--fix-boundary"]),
        ("butterworth order 3 (a real pole)", "butterworth", ["--order", "3"]),
        ("butterworth on the intrinsic Delaunay operator", "butterworth", ["--operator", "intrinsic"]),
        ("polezero with two poles", "polezero", ["--p1", "40", "--p2", "900"]),
    ]
    return out


def bumpy_case(directory):
    """A sphere covered with Gaussian bumps as a binary PLY, and the selection of one of them."""
    bare, bumpy, faces, centres = shapes.bumpy_sphere(5, 60, BUMP_RADIUS)
    mesh = os.path.join(directory, "bumpy.ply")
    mpi_harness.write_binary_ply(mesh, bumpy, faces)
    bumpy = cli_harness.read_mesh(mesh).vertices  # as stored (float)
    centre = bumpy[np.argmin(np.sum((bare - centres[0]) ** 2, axis=1))]
    return mesh, ["--select-sphere", ",".join(f"{x:.6f}" for x in centre) + f",{BUMP_RADIUS}"]


def noisy_sphere(directory):
    """An icosphere (2,562 vertices) with Gaussian noise along its normals, as a binary PLY."""
    vertices, faces = shapes.icosphere(4)
    vertices = np.asarray(vertices, float)
    normals = vertices / np.linalg.norm(vertices, axis=1)[:, None]
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    h = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1).mean()
    noise = NOISE * h * np.random.default_rng(20261205).standard_normal(len(vertices))
    path = os.path.join(directory, "noisy_sphere.ply")
    mpi_harness.write_binary_ply(path, vertices + noise[:, None] * normals, faces)
    return path


def noisy_cloud(directory):
    """3,000 points on the unit sphere with 1 % radial noise and no faces, as a binary PLY."""
    points = fibonacci_sphere(3000, 1.0) * (1 + 0.01 * np.random.default_rng(20261205).standard_normal((3000, 1)))
    path = os.path.join(directory, "cloud.ply")
    mpi_harness.write_binary_ply(path, points, np.zeros((0, 3), dtype=int))
    return path


def write_references():
    """geofilter on every case of every rank count, once: the outputs and what geofilter printed."""
    directory = references_dir()
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    mesh = mpi_harness.real_mesh_as_binary_ply(directory)
    vertices = cli_harness.read_mesh(mesh).vertices
    bumpy, select = bumpy_case(directory)
    runs = [(name, preset, options, mesh, True) for name, preset, options in cases(vertices, DENOISE_RANKS)]
    runs += [("denoise of a selected bump", "denoise", select, bumpy, True),
             ("denoise of sampling noise", "denoise", [], noisy_sphere(directory), True),
             ("lowpass of a point cloud", "lowpass", ["--radius", "0.3"], noisy_cloud(directory), True),
             ("measure", "measure", feature_selection(vertices), mesh, False)]
    printed = {}
    for name, preset, options, source, writes in runs:
        output = [os.path.join(directory, slug(name) + ".ply")] if writes else []
        single = cli_harness.run(preset, *options, source, *output, timeout=300)
        if single.returncode != 0:
            raise SystemExit(f"geofilter failed on {name}:\n" + cli_harness.describe(single))
        printed[name] = {"stdout": single.stdout, "stderr": single.stderr}
    with open(os.path.join(directory, "printed.json"), "w") as out:
        json.dump(printed, out)
    print(f"{len(printed)} references in {directory}")


class PresetsMatchGeofilter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = cli_harness.workdir(f"mpi_presets_np{RANKS}")
        cls.references = references_dir()
        printed = os.path.join(cls.references, "printed.json")
        if not os.path.exists(printed):
            raise AssertionError(f"{printed} is missing: run through ctest (mpi.references writes it), or"
                                 " `python3 test_mpi_presets.py --references` first")
        with open(printed) as f:
            cls.printed = json.load(f)
        cls.mesh = os.path.join(cls.references, "bunny00_binary.ply")
        vertices = cli_harness.read_mesh(cls.mesh).vertices
        cls.diagonal = float(np.linalg.norm(vertices.max(0) - vertices.min(0)))
        cls.input = vertices

    def test_every_preset_matches_geofilter(self):
        for index, (name, preset, options) in enumerate(cases(self.input)):
            with self.subTest(case=name):
                reference = os.path.join(self.references, slug(name) + ".ply")
                distributed = os.path.join(self.dir, f"{index}_np{RANKS}.ply")
                self.assertIn(name, self.printed, "the references were written for other cases: rerun mpi.references")
                single_stdout = self.printed[name]["stdout"]
                p = mpi_harness.run_mpi(RANKS, preset, *options, self.mesh, distributed)
                self.assertEqual(p.returncode, 0, cli_harness.describe(p))
                self.assertEqual(mpi_harness.read_by_slices(p), reads_by_slices(preset, options),
                                 f"{name}: read the mesh the wrong way\n" + p.stderr)
                # A pair geofilter solves exactly, geofilter-mpi solves exactly too (and no other).
                self.assertEqual("solved exactly" in p.stdout, "solved exactly" in single_stdout,
                                 f"{name}: the two tools solved a pole pair differently\n" + p.stdout)
                expected = cli_harness.read_mesh(reference).vertices
                got = cli_harness.read_mesh(distributed).vertices
                self.assertEqual(got.shape, expected.shape)
                # The filter moved the mesh: agreeing with geofilter is not agreeing with the input.
                self.assertGreater(np.abs(expected - self.input).max(), 1e3 * AGREEMENT * self.diagonal, name)
                worst = np.abs(got - expected).max() / self.diagonal
                print(f"{name}: differs by {worst:.3g} of the diagonal", file=sys.stderr)
                self.assertLess(worst, AGREEMENT, f"{name}: differs from geofilter by {worst:.3g} of the diagonal")

    def assert_agrees(self, name, before, reference, distributed):
        """geofilter-mpi's output within AGREEMENT of geofilter's, which moved the mesh."""
        expected = cli_harness.read_mesh(reference).vertices
        got = cli_harness.read_mesh(distributed).vertices
        diagonal = float(np.linalg.norm(before.max(0) - before.min(0)))
        self.assertGreater(np.abs(expected - before).max(), 1e3 * AGREEMENT * diagonal)
        worst = np.abs(got - expected).max() / diagonal
        print(f"{name}: differs by {worst:.3g} of the diagonal", file=sys.stderr)
        self.assertLess(worst, AGREEMENT, f"{name}: differs from geofilter by {worst:.3g} of the diagonal")

    def test_denoise_of_a_selected_bump_matches_geofilter(self):
        # The bunny has no pattern of bumps (Denoise leaves it as it was): a sphere covered with
        # Gaussian bumps, one of them selected. Denoise takes rank 0's whole-mesh path.
        name = "denoise of a selected bump"
        mesh = os.path.join(self.references, "bumpy.ply")
        bumpy, select = bumpy_case(self.dir)
        self.assertTrue(np.array_equal(cli_harness.read_mesh(bumpy).vertices, cli_harness.read_mesh(mesh).vertices),
                        "the references were written for another bumpy sphere: rerun mpi.references")
        bumpy = cli_harness.read_mesh(mesh).vertices
        reference = os.path.join(self.references, slug(name) + ".ply")
        distributed = os.path.join(self.dir, f"bumpy_np{RANKS}.ply")
        self.assertIn("pattern of bumps removed", self.printed[name]["stderr"])
        p = mpi_harness.run_mpi(RANKS, "denoise", *select, mesh, distributed)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        self.assertFalse(mpi_harness.read_by_slices(p), p.stderr)
        self.assert_agrees(name, bumpy, reference, distributed)

    @unittest.skipUnless(RANKS == DENOISE_RANKS, f"at {DENOISE_RANKS} ranks only (a whole filter per candidate)")
    def test_denoise_of_sampling_noise_matches_geofilter(self):
        name = "denoise of sampling noise"
        mesh = os.path.join(self.references, "noisy_sphere.ply")
        noisy = cli_harness.read_mesh(mesh).vertices
        reference = os.path.join(self.references, slug(name) + ".ply")
        distributed = os.path.join(self.dir, f"noisy_sphere_np{RANKS}.ply")
        self.assertIn("risk estimate", self.printed[name]["stderr"])
        p = mpi_harness.run_mpi(RANKS, "denoise", mesh, distributed)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        self.assert_agrees(name, noisy, reference, distributed)

    def test_a_point_cloud_matches_geofilter(self):
        # A cloud (no faces) takes rank 0's path: its Laplacian is built there, then solved
        # over the ranks like a mesh's.
        name = "lowpass of a point cloud"
        mesh = os.path.join(self.references, "cloud.ply")
        cloud = cli_harness.read_mesh(mesh)
        self.assertEqual(len(cloud.faces), 0)
        self.assertIn("point cloud", self.printed[name]["stderr"] + self.printed[name]["stdout"])
        distributed = os.path.join(self.dir, f"cloud_np{RANKS}.ply")
        p = mpi_harness.run_mpi(RANKS, "lowpass", "--radius", "0.3", mesh, distributed)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        self.assertFalse(mpi_harness.read_by_slices(p), p.stderr)
        self.assert_agrees(name, cloud.vertices, os.path.join(self.references, slug(name) + ".ply"), distributed)

    def test_measure_reports_what_geofilter_reports(self):
        ear = feature_selection(self.input)
        p = mpi_harness.run_mpi(RANKS, "measure", *ear, self.mesh)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        summary = [l for l in p.stdout.splitlines() if l.startswith("geofilter-mpi: measure:")]
        self.assertEqual(len(summary), 1, cli_harness.describe(p))
        self.assertIn(summary[0][len("geofilter-mpi"):], self.printed["measure"]["stdout"])


if __name__ == "__main__":
    if sys.argv[1:] == ["--references"]:
        write_references()
    else:
        unittest.main()
