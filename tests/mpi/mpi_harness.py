"""Runs `geofilter-mpi` under mpirun and `geofilter` (the single-process reference, whose
factored solver is the core's CHOLMOD path) on the same mesh and options."""

import os
import subprocess

import cli_harness

HERE = os.path.dirname(os.path.abspath(__file__))
REAL_MESH = os.path.join(HERE, "..", "..", "meshes", "bunny00.off")  # 37,706 vertices


def mpi_tool():
    path = os.environ.get("GEOFILTER_MPI_CLI", "")
    if not os.access(path, os.X_OK):
        raise AssertionError(f"no geofilter-mpi at {path!r}: build it (needs MPI and PETSc) and run through ctest")
    return path


def real_mesh():
    if not os.path.exists(REAL_MESH):
        raise AssertionError(f"{REAL_MESH} is missing: run scripts/fetch-meshes.sh (scripts/setup.sh does)")
    return os.path.abspath(REAL_MESH)


def run_mpi(ranks, *args, timeout=300):
    """geofilter-mpi on `ranks` processes; the environment (ctest's) lets mpirun run as root
    and oversubscribe the machine's cores."""
    mpiexec = os.environ.get("GEOFILTER_MPIEXEC", "mpirun")
    command = [mpiexec, "--oversubscribe", "-np", str(ranks), mpi_tool(), *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, errors="replace", timeout=timeout,
                          stdin=subprocess.DEVNULL)


def error_lines(p):
    """The tool's own error lines (mpirun's notices about a non-zero exit are not ours)."""
    return [l for l in p.stderr.splitlines() if l.startswith("geofilter-mpi: error:")]
