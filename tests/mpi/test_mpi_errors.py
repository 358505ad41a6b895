"""Bad input under MPI: one error line from the tool (not one per rank), a non-zero exit,
no output file, and no rank left waiting (the run ends well within its timeout)."""

import os
import unittest

import cli_harness
import mpi_harness

RANKS = 3


class BadInputUnderMpi(unittest.TestCase):
    def setUp(self):
        self.dir = cli_harness.workdir(self.id())
        self.output = os.path.join(self.dir, "out.ply")

    def refused(self, *args, expect, status=1, ranks=RANKS):
        p = mpi_harness.run_mpi(ranks, *args, timeout=120)
        self.assertEqual(p.returncode, status, cli_harness.describe(p))
        errors = mpi_harness.error_lines(p)
        self.assertEqual(len(errors), 1, "expected exactly one error line\n" + cli_harness.describe(p))
        self.assertIn(expect, errors[0])
        self.assertFalse(os.path.exists(self.output), "an output file was written")
        self.assertEqual(sorted(os.listdir(self.dir)), sorted(self.inputs()), "files left behind")
        return p

    def inputs(self):
        return [f for f in os.listdir(self.dir) if f.startswith("in")]

    def test_missing_file(self):
        self.refused("lowpass", os.path.join(self.dir, "missing.off"), self.output, expect="missing.off")

    def test_refused_design(self):
        # G1 = 1 leaves eq. 15 without a solution.
        self.refused("custom", "--G1", "1", mpi_harness.real_mesh(), self.output, expect="G1")

    def test_unstable_design(self):
        # A denominator with a root at s = 21.56: a pole where the mesh has frequencies.
        self.refused("custom", "--s1", "25", "--s2", "10", "--G0", "1", "--G1", "3", mpi_harness.real_mesh(),
                     self.output, expect="unstable")

    def test_nan_coordinate(self):
        path = os.path.join(self.dir, "in_nan.off")
        with open(path, "w") as f:
            f.write("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\nnan 1 1\n3 0 1 2\n3 1 3 2\n")
        before = open(path, "rb").read()
        self.refused("lowpass", path, self.output, expect="vertex 3")
        self.assertEqual(open(path, "rb").read(), before, "the input was changed")

    def test_failure_inside_the_distributed_solve(self):
        # Every rank runs the same CG (a Butterworth's pairs share one real factor, so none is
        # solved exactly); each sees it fail, rank 0 alone says so.
        self.refused("butterworth", "--max-iterations", "1", mpi_harness.real_mesh(), self.output,
                     expect="did not converge")

    def test_region_filters_are_refused_by_name(self):
        self.refused("exaggerate", "--region", "selected", "--select-sphere", "0,0,0,0.05", mpi_harness.real_mesh(),
                     self.output, expect="--region")

    def test_paper_solver_is_refused_by_name(self):
        self.refused("lowpass", "--solver", "pcg", mpi_harness.real_mesh(), self.output, expect="--solver")

    def test_bad_command_line(self):
        self.refused("lowpass", "--pole-solver", "fastest", mpi_harness.real_mesh(), self.output, expect="--pole-solver",
                     status=2)
        self.refused("lowpass", "--no-such-option", mpi_harness.real_mesh(), self.output, expect="--no-such-option",
                     status=2)


if __name__ == "__main__":
    unittest.main()
