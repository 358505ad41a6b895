"""geofilter-mpi --pole-solver multigrid (CG with a hypre BoomerAMG preconditioner, no
factor) against geofilter's factored result. Both stop on bounds of the error to the exact
filter at the tolerance (the area-weighted RMS distance, as a fraction of the diagonal), so
they may differ by at most twice the tolerance in that measure."""

import os
import unittest

import numpy as np

import cli_harness
import mpi_harness

RANKS = 2
TOLERANCE = 1e-7  # geofilter's default --tolerance


def lumped_mass(vertices, faces):
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    mass = np.zeros(len(vertices))
    for k in range(3):
        np.add.at(mass, faces[:, k], area / 3)
    return mass


class MultigridMatchesGeofilter(unittest.TestCase):
    def test_presets_within_the_tolerance(self):
        mesh = mpi_harness.real_mesh()
        work = cli_harness.workdir("mpi_multigrid")
        data = cli_harness.read_mesh(mesh)
        diagonal = float(np.linalg.norm(data.vertices.max(0) - data.vertices.min(0)))
        mass = lumped_mass(data.vertices, data.faces)
        # Complex pairs (the notch's, one of Butterworth's of order 3) and real poles (Butterworth's
        # third, the highpass's). The lowpass's pair is left out: the same path, at 454 CG
        # iterations (28 s) the slowest case.
        for preset, options in [("notch", []), ("butterworth", ["--order", "3"]), ("highpass", [])]:
            with self.subTest(preset=preset):
                reference = os.path.join(work, f"{preset}_reference.ply")
                distributed = os.path.join(work, f"{preset}_multigrid.ply")
                p = cli_harness.run(preset, *options, mesh, reference, timeout=300)
                self.assertEqual(p.returncode, 0, cli_harness.describe(p))
                p = mpi_harness.run_mpi(RANKS, preset, *options, "--pole-solver", "multigrid", mesh, distributed)
                self.assertEqual(p.returncode, 0, cli_harness.describe(p))
                self.assertNotIn("MUMPS factor", p.stderr, "the multigrid run built a factor")
                summary = [l for l in p.stdout.splitlines() if l.startswith(f"geofilter-mpi: {preset}:")]
                self.assertEqual(len(summary), 1, cli_harness.describe(p))
                self.assertIn("BoomerAMG", summary[0], "the summary names another solver than the one that ran")
                self.assertNotIn("factored", summary[0], "the summary claims a factorisation")
                expected = cli_harness.read_mesh(reference).vertices
                got = cli_harness.read_mesh(distributed).vertices
                self.assertGreater(np.abs(expected - data.vertices).max(), 1e3 * TOLERANCE * diagonal)
                rms = np.sqrt((mass * ((got - expected) ** 2).sum(1)).sum() / mass.sum()) / diagonal
                self.assertLess(rms, 2 * TOLERANCE, f"{preset}: RMS difference {rms:.3g} of the diagonal")


if __name__ == "__main__":
    unittest.main()
