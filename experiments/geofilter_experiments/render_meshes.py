"""Renders triangle meshes (OFF or PLY) side by side into one PNG, headless.

    experiments/run geofilter_experiments.render_meshes OUT.png [--view AZIMUTH,ELEVATION] [--up x|y|z] FILE[=TITLE] ...

Orthographic view, flat Lambert shading, back-to-front painting with matplotlib's
PolyCollection: enough to judge a filter's effect by eye.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from geofilter_harness import read_ply  # noqa: E402  (tests/integration, on the path through experiments/run)


def read_off(path):
    with open(path) as f:
        tokens = f.read().split()
    if tokens[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    v = np.array(tokens[pos:pos + 3 * nv], dtype=float).reshape(nv, 3)
    pos += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(tokens[pos])
        idx = [int(t) for t in tokens[pos + 1:pos + 1 + k]]
        pos += 1 + k
        faces += [(idx[0], idx[j], idx[j + 1]) for j in range(1, k - 1)]
    return v, np.array(faces, dtype=int)


def read_mesh(path):
    if path.lower().endswith(".off"):
        return read_off(path)
    m = read_ply(path)
    return np.asarray(m.vertices, dtype=float), np.asarray(m.faces, dtype=int)


def view_matrix(azimuth, elevation, up):
    # Rotate so that `up` becomes +y, then turn by azimuth about y and tilt by elevation.
    to_y = {"y": np.eye(3), "z": np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]]),
            "x": np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]])}[up]
    a, e = np.radians(azimuth), np.radians(elevation)
    turn = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    tilt = np.array([[1, 0, 0], [0, np.cos(e), -np.sin(e)], [0, np.sin(e), np.cos(e)]])
    return tilt @ turn @ to_y


def draw(ax, v, f, rotation, title):
    p = v @ rotation.T
    tri = p[f]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    light = np.array([0.4, 0.5, 0.75])
    light /= np.linalg.norm(light)
    shade = 0.25 + 0.75 * np.abs(normals @ light)
    order = np.argsort(tri[:, :, 2].mean(axis=1))  # far (small z) first
    colors = np.outer(shade[order], [0.80, 0.78, 0.72])
    ax.add_collection(PolyCollection(tri[order][:, :, :2], facecolors=colors, edgecolors="none", antialiased=False))
    lo, hi = p[:, :2].min(0), p[:, :2].max(0)
    pad = 0.05 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(title, fontsize=10)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("meshes", nargs="+", help="FILE or FILE=TITLE")
    ap.add_argument("--view", default="0,15", help="azimuth,elevation in degrees")
    ap.add_argument("--up", default="y", choices="xyz")
    args = ap.parse_args()
    az, el = (float(x) for x in args.view.split(","))
    rotation = view_matrix(az, el, args.up)
    fig, axes = plt.subplots(1, len(args.meshes), figsize=(4.2 * len(args.meshes), 4.4), squeeze=False)
    for ax, spec in zip(axes[0], args.meshes):
        path, _, title = spec.partition("=")
        v, f = read_mesh(path)
        draw(ax, v, f, rotation, title or os.path.basename(path))
    fig.tight_layout()
    fig.savefig(args.out, dpi=110, bbox_inches="tight", pad_inches=0.1)  # tall meshes: keep the titles
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
