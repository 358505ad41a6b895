"""GeoFilter against 50 steps of MeshLab's Taubin Smooth, through meshlabserver, I/O included.

The mesh is diplodocus.off midpoint-subdivided twice (383,682 vertices: the size of a
mid-sized scan), scaled to unit bounding-box diagonal, as binary PLY. Each row is the wall
time of one `meshlabserver -i in.ply -o out.ply -s script.mlx` run (best of --repeat), so
start-up, reading and writing count for every filter alike. Prints a Markdown table.
Run by scripts/benchmark-meshlab.sh, which sets PYTHONPATH to the meshlabserver harness.
"""
import argparse
import os
import re
import struct
import tempfile
import time

import numpy as np

import geofilter_harness as h


def read_off(path):
    with open(path) as f:
        tokens = f.read().split()
    assert tokens[0] == "OFF"
    nv, nf = int(tokens[1]), int(tokens[2])
    v = np.array(tokens[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    f = np.array(tokens[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=np.int64).reshape(nf, 4)[:, 1:]
    return v, f


def subdivide(v, f):
    """Every triangle split in four at its edge midpoints."""
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(v) + inverse.reshape(3, -1).T  # midpoints of edges 01, 12, 20 of each face
    v = np.vstack([v, 0.5 * (v[unique[:, 0]] + v[unique[:, 1]])])
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    ab, bc, ca = mid[:, 0], mid[:, 1], mid[:, 2]
    f = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return v, f


def write_ply_binary(path, v, f):
    with open(path, "wb") as out:
        out.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\nproperty float x\n"
                   f"property float y\nproperty float z\nelement face {len(f)}\n"
                   "property list uchar int vertex_indices\nend_header\n").encode())
        out.write(v.astype("<f4").tobytes())
        faces = np.empty(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        faces["n"] = 3
        faces["i"] = f
        out.write(faces.tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--meshes", required=True)
    ap.add_argument("--out", required=True, help="directory for the table (meshlabserver.md)")
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()

    v, f = read_off(os.path.join(args.meshes, "diplodocus.off"))
    for _ in range(2):
        v, f = subdivide(v, f)
    lo, hi = v.min(axis=0), v.max(axis=0)
    v = (v - 0.5 * (lo + hi)) / np.linalg.norm(hi - lo)

    rows = [
        ("Taubin Smooth, 50 steps (λ = 0.5, μ = -0.53)", h.Step("Taubin Smooth", [
            (h.Param("lambda", "RichFloat", 0.5), 0.5), (h.Param("mu", "RichFloat", -0.53), -0.53),
            (h.Param("stepSmoothNum", "RichInt", 10), 50), (h.Param("Selected", "RichBool", False), False)])),
        ("GeoFilter Lowpass (25, 50, 1, 1.1, 0)", h.geofilter("GeoFilter: Lowpass", tolerance=1e-7)),
        ("GeoFilter Band Exaggeration (25, 60, 1, 3, 0.9)", h.geofilter(
            "GeoFilter: Band Exaggeration", s1=25, s2=60, G0=1, G1=3, Ginf=0.9, tolerance=1e-7)),
        ("GeoFilter Notch (630, 1260, 1, 0.01, 1.1)", h.geofilter(
            "GeoFilter: Notch", s1=630, s2=1260, G0=1, G1=0.01, Ginf=1.1, tolerance=1e-7)),
        ("GeoFilter Butterworth Lowpass (cutoff 25, order 4)", h.geofilter(
            "GeoFilter: Butterworth Lowpass", cutoff=25, order=4, tolerance=1e-7)),
    ]
    with tempfile.TemporaryDirectory(prefix="geofilter-bench-") as work:
        mesh = os.path.join(work, "in.ply")
        write_ply_binary(mesh, v, f)
        results = []
        for label, step in rows:
            best, log_time = float("inf"), ""
            for _ in range(args.repeat):
                t0 = time.monotonic()
                run = h.run_meshlabserver(work, [step], inputs=[mesh], outputs=[(os.path.join(work, "out.ply"), None)],
                                          timeout=1800)
                seconds = time.monotonic() - t0
                if run.returncode != 0:
                    raise SystemExit(f"{label} failed:\n{run.describe()}")
                if seconds < best:
                    best = seconds
                    m = re.search(r"CG iterations.*; time ([0-9.e+-]+) s", "\n".join(run.log))
                    log_time = m.group(1) if m else ""
            results.append((label, best, log_time))
            print(f"{label}: {best:.2f} s", flush=True)
    taubin = results[0][1]
    table = [f"diplodocus subdivided twice: {len(v):,} vertices, {len(f):,} faces, binary PLY, unit diagonal; "
             f"meshlabserver wall time, best of {args.repeat}, I/O and start-up included.", "",
             "| filter | meshlabserver (s) | of which the filter (s, its log) | / Taubin x50 |",
             "|---|---:|---:|---:|"]
    for label, seconds, log_time in results:
        table.append(f"| {label} | {seconds:.2f} | {log_time or '—'} | {seconds / taubin:.2f} |")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "meshlabserver.md"), "w") as out:
        out.write("\n".join(table) + "\n")
    print("\n".join(table))


if __name__ == "__main__":
    main()
