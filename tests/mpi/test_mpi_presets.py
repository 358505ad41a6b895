"""geofilter-mpi on N ranks gives geofilter's coordinates on a real mesh for every preset of
the filter table (and the feature, operator and boundary options that reach the solver),
to 1e-7 of the bounding-box diagonal. N comes from $GEOFILTER_MPI_RANKS (one ctest per N).
The mesh is a binary PLY, so that the presets on the cotangent Laplacian of the whole mesh
take the path that reads, assembles and writes by slices, and the others (Denoise, the
fixed boundary, another operator) the path where rank 0 reads the mesh."""

import os
import sys
import unittest

import numpy as np

import cli_harness
import filter_table
import mpi_harness
import shapes

RANKS = int(os.environ.get("GEOFILTER_MPI_RANKS", "2"))
AGREEMENT = 1e-7  # of the bounding-box diagonal, at every vertex


def feature_selection(vertices):
    """A ball of radius 0.06 about the bunny's highest vertex (the tip of an ear)."""
    top = vertices[np.argmax(vertices[:, 1])]
    return ["--select-sphere", ",".join(f"{c:.6f}" for c in top) + ",0.06"]


def reads_by_slices(preset, options):
    """Which runs geofilter-mpi should read by slices."""
    return preset != "denoise" and "--fix-boundary" not in options and "--operator" not in options


def cases(vertices):
    """(name, preset, options): every filter of the table at its defaults, then the options
    that change what the distributed solver is given."""
    out = [(f["cli_name"], f["cli_name"], []) for f in filter_table.TABLE if f["kind"] != "Measure"]
    assert len(out) >= 9, "the filter table lost its presets"
    assert any(case[1] == "denoise" for case in out), "the filter table lost Denoise"
    if RANKS != 2:
        # Denoise with nothing selected runs a whole filter per candidate cutoff through the
        # distributed solver (a factorisation per candidate, 90 s at two ranks on two cores): at two
        # ranks only. Every rank count still runs Denoise of a selected bump (below), which takes
        # the same rank-0 path, and every preset's distributed solve.
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


class PresetsMatchGeofilter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = cli_harness.workdir(f"mpi_presets_np{RANKS}")
        cls.mesh = mpi_harness.real_mesh_as_binary_ply(cls.dir)
        vertices = cli_harness.read_mesh(cls.mesh).vertices
        cls.diagonal = float(np.linalg.norm(vertices.max(0) - vertices.min(0)))
        cls.input = vertices

    def test_every_preset_matches_geofilter(self):
        for index, (name, preset, options) in enumerate(cases(self.input)):
            with self.subTest(case=name):
                reference = os.path.join(self.dir, f"{index}_reference.ply")
                distributed = os.path.join(self.dir, f"{index}_np{RANKS}.ply")
                single = cli_harness.run(preset, *options, self.mesh, reference, timeout=300)
                self.assertEqual(single.returncode, 0, cli_harness.describe(single))
                p = mpi_harness.run_mpi(RANKS, preset, *options, self.mesh, distributed)
                self.assertEqual(p.returncode, 0, cli_harness.describe(p))
                self.assertEqual(mpi_harness.read_by_slices(p), reads_by_slices(preset, options),
                                 f"{name}: read the mesh the wrong way\n" + p.stderr)
                # A pair geofilter solves exactly, geofilter-mpi solves exactly too (and no other).
                self.assertEqual("solved exactly" in p.stdout, "solved exactly" in single.stdout,
                                 f"{name}: the two tools solved a pole pair differently\n" + p.stdout)
                expected = cli_harness.read_mesh(reference).vertices
                got = cli_harness.read_mesh(distributed).vertices
                self.assertEqual(got.shape, expected.shape)
                # The filter moved the mesh: agreeing with geofilter is not agreeing with the input.
                self.assertGreater(np.abs(expected - self.input).max(), 1e3 * AGREEMENT * self.diagonal, name)
                worst = np.abs(got - expected).max() / self.diagonal
                print(f"{name}: differs by {worst:.3g} of the diagonal", file=sys.stderr)
                self.assertLess(worst, AGREEMENT, f"{name}: differs from geofilter by {worst:.3g} of the diagonal")

    def test_denoise_of_a_selected_bump_matches_geofilter(self):
        # The bunny has no pattern of bumps (Denoise leaves it as it was): a sphere covered with
        # Gaussian bumps, one of them selected. Denoise takes rank 0's whole-mesh path.
        rho = 0.15
        bare, bumpy, faces, centres = shapes.bumpy_sphere(5, 60, rho)
        mesh = os.path.join(self.dir, "bumpy.ply")
        mpi_harness.write_binary_ply(mesh, bumpy, faces)
        bumpy = cli_harness.read_mesh(mesh).vertices  # as stored (float)
        centre = bumpy[np.argmin(np.sum((bare - centres[0]) ** 2, axis=1))]
        select = ["--select-sphere", ",".join(f"{x:.6f}" for x in centre) + f",{rho}"]
        reference, distributed = (os.path.join(self.dir, f"bumpy_{tag}.ply") for tag in ("reference", f"np{RANKS}"))
        single = cli_harness.run("denoise", *select, mesh, reference, timeout=300)
        self.assertEqual(single.returncode, 0, cli_harness.describe(single))
        self.assertIn("pattern of bumps removed", single.stderr)
        p = mpi_harness.run_mpi(RANKS, "denoise", *select, mesh, distributed)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        self.assertFalse(mpi_harness.read_by_slices(p), p.stderr)
        expected = cli_harness.read_mesh(reference).vertices
        got = cli_harness.read_mesh(distributed).vertices
        diagonal = float(np.linalg.norm(bumpy.max(0) - bumpy.min(0)))
        self.assertGreater(np.abs(expected - bumpy).max(), 1e3 * AGREEMENT * diagonal)
        worst = np.abs(got - expected).max() / diagonal
        print(f"denoise of a selected bump: differs by {worst:.3g} of the diagonal", file=sys.stderr)
        self.assertLess(worst, AGREEMENT, f"differs from geofilter by {worst:.3g} of the diagonal")

    def test_measure_reports_what_geofilter_reports(self):
        ear = feature_selection(self.input)
        single = cli_harness.run("measure", *ear, self.mesh)
        self.assertEqual(single.returncode, 0, cli_harness.describe(single))
        p = mpi_harness.run_mpi(RANKS, "measure", *ear, self.mesh)
        self.assertEqual(p.returncode, 0, cli_harness.describe(p))
        summary = [l for l in p.stdout.splitlines() if l.startswith("geofilter-mpi: measure:")]
        self.assertEqual(len(summary), 1, cli_harness.describe(p))
        self.assertIn(summary[0][len("geofilter-mpi"):], single.stdout)


if __name__ == "__main__":
    unittest.main()
