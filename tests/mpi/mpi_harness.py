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


def write_binary_ply(path, vertices, faces, double=False, normals=False, quality=None, polygons=()):
    """A binary little-endian PLY of `faces` (triangles), as scanners and MeshLab write them:
    what geofilter-mpi reads by slices. `normals` adds nx, ny, nz (zeros: the input's, made
    stale by the filter), `quality` a per-vertex float; `polygons` are appended as faces of
    more corners."""
    import numpy as np
    v = np.asarray(vertices, float)
    scalar = "<f8" if double else "<f4"
    fields = [("x", scalar), ("y", scalar), ("z", scalar)]
    if normals:
        fields += [("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4")]
    if quality is not None:
        fields.append(("quality", "<f4"))
    records = np.zeros(len(v), dtype=fields)
    for k, name in enumerate("xyz"):
        records[name] = v[:, k]
    if quality is not None:
        records["quality"] = quality
    names = {"<f8": "double", "<f4": "float"}
    header = ["ply", "format binary_little_endian 1.0", "comment written by the geofilter-mpi tests",
              f"element vertex {len(v)}"]
    header += [f"property {names[t]} {n}" for n, t in fields]
    header += [f"element face {len(faces) + len(polygons)}", "property list uchar int vertex_indices", "end_header"]
    triangles = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    triangles["n"] = 3
    triangles["i"] = np.asarray(faces)
    with open(path, "wb") as out:
        out.write(("\n".join(header) + "\n").encode("ascii"))
        out.write(records.tobytes())
        out.write(triangles.tobytes())
        for polygon in polygons:
            out.write(np.uint8(len(polygon)).tobytes() + np.asarray(polygon, "<i4").tobytes())


def real_mesh_as_binary_ply(directory):
    """The real mesh as a binary PLY of float positions (what geofilter-mpi reads by slices)."""
    path = os.path.join(directory, "bunny00_binary.ply")
    mesh = cli_harness.read_mesh(real_mesh())
    write_binary_ply(path, mesh.vertices, mesh.faces)
    return path


def read_by_slices(p):
    """Whether geofilter-mpi read the file by slices on every rank (its log says which path)."""
    return "geofilter-mpi: read by slices:" in p.stderr
