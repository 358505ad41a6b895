"""GeoFilter against 50 steps of MeshLab's Taubin Smooth, through meshlabserver, I/O included.

The mesh is diplodocus.off midpoint-subdivided twice (383,682 vertices: the size of a
mid-sized scan), scaled to unit bounding-box diagonal, with Gaussian noise of 0.3 mean edge
lengths along the normals (what Denoise is for; the other filters' cost does not depend on
it), as binary PLY. A run is one `meshlabserver -i in.ply -o out.ply -s script.mlx`, so
start-up, reading and writing count for every filter alike. The rows are run in rounds, each
round in a rotated order, so that a slow spell of the machine falls on every row alike; each
row reports the median of its --repeat runs (at least 3) and their range, and its ratio to
Taubin's median of the same rounds. Writes results/benchmark/meshlabserver.md and, run with the
defaults, the page docs/results/meshlabserver.md. Run by scripts/benchmark-meshlab.sh, which
sets PYTHONPATH to the meshlabserver harness and the experiments' page writer.
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


def noise_along_normals(v, f, edges, seed):
    """Gaussian offsets of `edges` mean edge lengths along the area-weighted vertex normals."""
    n = np.zeros_like(v)
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    for k in range(3):
        np.add.at(n, f[:, k], cross)
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    h = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1).mean()
    return (edges * h * np.random.default_rng(seed).standard_normal(len(v)))[:, None] * n


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


def median(values):
    return float(np.median(values))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--meshes", required=True)
    ap.add_argument("--out", required=True, help="directory for the table (meshlabserver.md)")
    ap.add_argument("--repeat", type=int, default=3, help="rounds (at least 3)")
    args = ap.parse_args()
    if args.repeat < 3:
        raise SystemExit("--repeat: a median needs at least 3 runs")

    v, f = read_off(os.path.join(args.meshes, "diplodocus.off"))
    for _ in range(2):
        v, f = subdivide(v, f)
    lo, hi = v.min(axis=0), v.max(axis=0)
    v = (v - 0.5 * (lo + hi)) / np.linalg.norm(hi - lo)
    v = v + noise_along_normals(v, f, 0.3, seed=20261205)

    tight = dict(tolerance=1e-7)
    rows = [
        ("Taubin Smooth, 50 steps (λ = 0.5, μ = -0.53)", h.Step("Taubin Smooth", [
            (h.Param("lambda", "RichFloat", 0.5), 0.5), (h.Param("mu", "RichFloat", -0.53), -0.53),
            (h.Param("stepSmoothNum", "RichInt", 10), 50), (h.Param("Selected", "RichBool", False), False)])),
        ("GeoFilter Lowpass (s1 25, G1 1.1)", h.geofilter("GeoFilter: Lowpass", s1=25, **tight)),
        ("GeoFilter Band Exaggeration (25, 60, 1, 3, 0.9)", h.geofilter(
            "GeoFilter: Band Exaggeration", s1=25, s2=60, G0=1, G1=3, Ginf=0.9, **tight)),
        ("GeoFilter Notch (630, 1260, 1, 0.01, 1.1)", h.geofilter(
            "GeoFilter: Notch", s1=630, s2=1260, G0=1, G1=0.01, Ginf=1.1, **tight)),
        ("GeoFilter Butterworth Lowpass (cutoff 25, order 4)", h.geofilter(
            "GeoFilter: Butterworth Lowpass", cutoff=25, order=4, **tight)),
        ("GeoFilter Denoise (nothing selected)", h.geofilter("GeoFilter: Denoise")),
    ]
    times = {label: [] for label, _ in rows}
    profile = {label: [] for label, _ in rows}
    with tempfile.TemporaryDirectory(prefix="geofilter-bench-") as work:
        mesh = os.path.join(work, "in.ply")
        write_ply_binary(mesh, v, f)
        for round_ in range(args.repeat):
            for label, step in rows[round_ % len(rows):] + rows[:round_ % len(rows)]:
                t0 = time.monotonic()
                run = h.run_meshlabserver(work, [step], inputs=[mesh], outputs=[(os.path.join(work, "out.ply"), None)],
                                          timeout=1800)
                seconds = time.monotonic() - t0
                if run.returncode != 0:
                    raise SystemExit(f"{label} failed:\n{run.describe()}")
                times[label].append(seconds)
                # "time T s (assembly A, factorisation F, solve S)"; the Lanczos process has no factorisation.
                m = re.search(r"time ([0-9.e+-]+) s \(assembly ([0-9.e+-]+)(?:, factorisation ([0-9.e+-]+))?"
                              r"(?:, solve ([0-9.e+-]+))?", "\n".join(run.log))
                profile[label].append((seconds, m.groups() if m else None))
                print(f"round {round_ + 1}: {label}: {seconds:.2f} s", flush=True)
    taubin = times[rows[0][0]]
    reference = median(taubin)
    table = [f"diplodocus subdivided twice: {len(v):,} vertices, {len(f):,} faces, binary PLY, unit diagonal, noise "
             "0.3 mean edge lengths along the normals. meshlabserver wall time, I/O and start-up included; "
             f"{args.repeat} rounds, each in a rotated order; median (range) per row.", "",
             f"Taubin x50, the reference: median {reference:.2f} s, range {min(taubin):.2f}–{max(taubin):.2f} s "
             f"(spread {100 * (max(taubin) - min(taubin)) / reference:.0f} % of the median).", "",
             "| filter | meshlabserver, median (range) s | / Taubin x50 (medians) | the filter's own log, median run: "
             "total (stages) s; Denoise: its final lowpass's stages |",
             "|---|---:|---:|---|"]
    for label, _ in rows:
        t = times[label]
        mid = sorted(profile[label], key=lambda x: x[0])[len(t) // 2][1]
        log = "—" if mid is None else f"{mid[0]} ({', '.join(f'{name} {x}' for name, x in zip(('assembly', 'factorisation', 'solve'), mid[1:]) if x)})"
        table.append(f"| {label} | {median(t):.2f} ({min(t):.2f}–{max(t):.2f}) | {median(t) / reference:.2f} | {log} |")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "meshlabserver.md"), "w") as out:
        out.write("\n".join(table) + "\n")
    print("\n".join(table))
    if args.repeat == ap.get_default("repeat"):
        from geofilter_experiments import pages
        pages.write_page("meshlabserver", "\n".join(["# GeoFilter against 50 Taubin steps, through meshlabserver", "",
                                                     *table]), command="scripts/benchmark-meshlab.sh")


if __name__ == "__main__":
    main()
