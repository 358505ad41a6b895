"""Time and peak memory per rank of geofilter-mpi at several rank counts against the
single-process geofilter, on a procedural bumpy torus of a given size (binary PLY).
Prints a table; run through scripts/benchmark-mpi.sh. Not a test: nothing is asserted."""

import argparse
import os
import re
import resource
import subprocess
import sys
import time

import numpy as np


def bumpy_torus(vertices):
    """A torus (radii 1 and 0.35) with bumps of several sizes, as a grid of about `vertices`
    vertices: every vertex has six neighbours, like a scan's interior."""
    nv = max(8, int(round(np.sqrt(vertices / 2.5))))
    nu = max(8, int(round(vertices / nv)))
    u = np.linspace(0, 2 * np.pi, nu, endpoint=False)[:, None]
    v = np.linspace(0, 2 * np.pi, nv, endpoint=False)[None, :]
    r = 0.35 * (1 + 0.06 * np.sin(7 * u) * np.sin(5 * v) + 0.02 * np.sin(41 * u) * np.sin(23 * v))
    x = ((1 + r * np.cos(v)) * np.cos(u)).ravel()
    y = ((1 + r * np.cos(v)) * np.sin(u)).ravel()
    z = (r * np.sin(v) * np.ones_like(u)).ravel()
    points = np.stack([x, y, z], axis=1)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return points, faces


def write_binary_ply(path, points, faces):
    face_rows = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face_rows["n"] = 3
    face_rows["i"] = faces
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(points)}\nproperty double x\n"
                 f"property double y\nproperty double z\nelement face {len(faces)}\n"
                 "property list uchar int vertex_indices\nend_header\n").encode())
        f.write(np.ascontiguousarray(points, "<f8").tobytes())
        f.write(face_rows.tobytes())


def measured(command, env):
    """(wall seconds, peak RSS in MiB of the largest child, completed process), in a child
    of its own so that the peak is this command's alone."""
    probe = ("import resource, subprocess, sys, time; t = time.time(); "
             "p = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
             "print(time.time() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0, p.returncode); "
             "sys.stderr.write(p.stderr)")
    p = subprocess.run([sys.executable, "-c", probe, *command], capture_output=True, text=True, env=env)
    seconds, peak, status = p.stdout.split()
    if int(status) != 0:
        raise SystemExit(f"benchmark: {' '.join(command)} failed:\n{p.stderr}")
    return float(seconds), float(peak), p.stderr


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--geofilter", required=True)
    parser.add_argument("--geofilter-mpi", required=True)
    parser.add_argument("--mpirun", default="mpirun")
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--vertices", type=int, nargs="+", default=[2_000_000])
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--preset", default="lowpass")
    parser.add_argument("--pole-solver", default="direct")
    args = parser.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1")
    rows, notes = [], []
    for n in args.vertices:
        mesh = os.path.join(args.workdir, f"torus_{n}.ply")
        if not os.path.exists(mesh):
            points, faces = bumpy_torus(n)
            write_binary_ply(mesh, points, faces)
        out = os.path.join(args.workdir, "out.ply")
        seconds, peak, _ = measured([args.geofilter, args.preset, "-q", mesh, out], env)
        actual = int(re.search(rb"element vertex (\d+)", open(mesh, "rb").read(400)).group(1))
        rows.append((actual, "geofilter", 1, seconds, [peak]))
        for ranks in args.ranks:
            seconds, _, log = measured([args.mpirun, "--oversubscribe", "-np", str(ranks), args.geofilter_mpi,
                                        args.preset, "--pole-solver", args.pole_solver, mesh, out], env)
            m = re.search(r"peak memory per rank \(MiB\): ([\d. e+]+)", log)
            rows.append((actual, "geofilter-mpi", ranks, seconds, [float(x) for x in m.group(1).split()]))
            factor = re.search(r"MUMPS (?:factor|complex LDL\^T) [^;\n]*", log)
            before = re.search(r"rank 0 before the distributed solve[^:]*: peak ([\d.e+]+) MiB", log)
            notes.append(f"{actual} vertices, {ranks} rank(s): {factor.group(0) if factor else 'no factor'}; "
                         f"rank 0 held {before.group(1) if before else '?'} MiB before the distributed solve")
        os.remove(out)
    print(f"{'vertices':>10} {'tool':<14} {'ranks':>5} {'seconds':>8} {'peak MiB (max rank)':>20} "
          f"{'vs geofilter':>12}  per rank")
    single = {}
    for vertices, tool, ranks, seconds, peaks in rows:
        if tool == "geofilter":
            single[vertices] = peaks[0]
        share = max(peaks) / single[vertices]
        print(f"{vertices:>10} {tool:<14} {ranks:>5} {seconds:>8.1f} {max(peaks):>20.0f} {share:>11.0%}  "
              + " ".join(f"{p:.0f}" for p in peaks))
    for note in notes:
        print(note)


if __name__ == "__main__":
    main()
