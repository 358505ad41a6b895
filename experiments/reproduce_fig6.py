"""The paper's sphere test (section 5, Fig. 6) through meshlabserver.

    experiments/run reproduce_fig6 [--out results/figures]

A sphere of radius r is an eigenmode of the Laplace-Beltrami operator with s = 2/r^2, so the
Fig. 6 filter (s1 = 10, s2 = 25, G0 = 1, G1 = 30, Ginf = 0) should scale it by G(2/r^2).
Three tessellations, each at ~2,000 and ~120 vertices, 12 radii from 0.15 to 3:
  - icosahedral: MeshLab's own "Sphere" (icosahedron subdivided 4 / 2 times: 2,562 / 162 vertices);
  - tetrahedral: a tetrahedron split 1-to-4 five / three times, projected to the sphere after
    every split (2,050 / 130 vertices; valence-3 corners, long and short edges);
  - latitude/longitude: 31 rings of 64 / 7 rings of 16 vertices plus the poles (1,986 / 114
    vertices; high-valence poles and slivers near them).
The measured gain is the paper's r_O / r_I (mean distance of the vertices to their centroid,
output over input); its sign is checked with a least-squares scale factor, since G < 0 would
turn the sphere inside out with the same mean radius.
Writes fig6.png (|G| curve and the measured gains, log y) and fig6.md (the table and the
largest relative deviation per tessellation).
"""
import argparse
import os
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from geofilter_experiments import common as c  # noqa: E402
from geofilter_experiments import pages  # noqa: E402
from geofilter_experiments.common import h  # noqa: E402

FIG6 = dict(s1=10.0, s2=25.0, G0=1.0, G1=30.0, Ginf=0.0)
RADII = np.geomspace(0.15, 3.0, 12)
# (icosphere subdivisions, tetrahedron splits, (latitude bands, longitude segments)) per resolution:
# ~2,000 vertices, and ~120 where the discretisation error should show.
RESOLUTIONS = {"fine": (4, 5, (32, 64)), "coarse": (2, 3, (8, 16))}


def tetra_sphere(levels):
    v = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float) / np.sqrt(3)
    f = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    for _ in range(levels):
        verts = list(v)
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = (verts[a] + verts[b]) / 2
                verts.append(m / np.linalg.norm(m))  # project now: later splits see a sphere
                mid[key] = len(verts) - 1
            return mid[key]

        nf = []
        for a, b, cc in f:
            ab, bc, ca = midpoint(a, b), midpoint(b, cc), midpoint(cc, a)
            nf += [[a, ab, ca], [ab, b, bc], [ca, bc, cc], [ab, bc, ca]]
        v, f = np.array(verts), np.array(nf)
    return v, f


def latlong_sphere(n_lat, n_lon):
    theta = np.pi * np.arange(1, n_lat) / n_lat  # rings, poles excluded
    phi = 2 * np.pi * np.arange(n_lon) / n_lon
    T, F = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(T) * np.cos(F), np.sin(T) * np.sin(F), np.cos(T)], axis=-1).reshape(-1, 3)
    v = np.vstack([[0, 0, 1], ring, [0, 0, -1]])
    idx = lambda i, j: 1 + i * n_lon + (j % n_lon)
    south = len(v) - 1
    f = []
    for j in range(n_lon):
        f.append([0, idx(0, j), idx(0, j + 1)])
        f.append([south, idx(n_lat - 2, j + 1), idx(n_lat - 2, j)])
        for i in range(n_lat - 2):
            a, b, cc, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            f += [[a, b, cc], [a, cc, d]]
    return v, np.array(f)


def mean_radius(v):
    return float(np.linalg.norm(v - v.mean(0), axis=1).mean())


def scale_factor(v_in, v_out):
    """Least-squares g in (v_out - c_out) ~ g (v_in - c_in): signed, unlike the mean radius."""
    a, b = v_in - v_in.mean(0), v_out - v_out.mean(0)
    return float(np.sum(a * b) / np.sum(a * a))


def measure(workdir, tess, resolution):
    """(radius, r_O/r_I, signed scale, vertices, per-vertex spread) per radius, one meshlabserver run."""
    ico_subdiv, tetra_levels, latlong = RESOLUTIONS[resolution]
    tag = f"{tess}-{resolution}"
    steps, inputs, outputs = [c.select_none()], [], []
    gf = c.geofilter("GeoFilter: Custom", useSelection=False, **FIG6)
    for i, r in enumerate(RADII):
        if tess == "icosahedral":
            # MeshLab's Sphere adds a layer; keep an unfiltered copy (layer 2i) for r_I.
            steps += [h.sphere(float(r), ico_subdiv), c.duplicate_layer(), gf]
            outputs += [(os.path.join(workdir, f"{tag}-{i}-in.ply"), 2 * i), (os.path.join(workdir, f"{tag}-{i}.ply"), 2 * i + 1)]
        else:
            v, f = tetra_sphere(tetra_levels) if tess == "tetrahedral" else latlong_sphere(*latlong)
            path = os.path.join(workdir, f"{tag}-{i}-in.ply")
            h.write_ply_ascii(path, h.PlyMesh(v * r, f))
            inputs.append(path)
            steps += [c.current_layer(i), gf]
            outputs.append((os.path.join(workdir, f"{tag}-{i}.ply"), i))
    if tess == "icosahedral":
        steps = steps[1:]  # no mesh to deselect before the first Sphere
    c.run(workdir, steps, inputs=inputs, outputs=outputs, name=tag)
    rows = []
    for i, r in enumerate(RADII):
        vi = h.read_ply(os.path.join(workdir, f"{tag}-{i}-in.ply")).vertices
        vo = h.read_ply(os.path.join(workdir, f"{tag}-{i}.ply")).vertices
        # The mean radius averages out how unevenly the vertices moved; the per-vertex ratios do not.
        per_vertex = np.linalg.norm(vo - vo.mean(0), axis=1) / np.linalg.norm(vi - vi.mean(0), axis=1)
        g = h.eq15_gain(2 / r ** 2, **FIG6)
        rows.append((float(r), mean_radius(vo) / mean_radius(vi), scale_factor(vi, vo), len(vi),
                     float(np.abs(per_vertex / g - 1).max())))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "figures"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    G = lambda s: h.eq15_gain(s, **FIG6)
    results = {}  # (tessellation, resolution) -> rows
    with tempfile.TemporaryDirectory(prefix="fig6-") as work:
        for res in RESOLUTIONS:
            for tess in ("icosahedral", "tetrahedral", "latlong"):
                results[tess, res] = measure(work, tess, res)
                print(tess, res, " ".join(f"{r:.3g}:{g:.4g}" for r, g, *_ in results[tess, res]), flush=True)

    # Top: the paper's plot. Bottom: the deviations, too small to see on the log axis above.
    fig, (ax, axd) = plt.subplots(2, 1, figsize=(7.5, 7), sharex=True, gridspec_kw={"height_ratios": [2.2, 1]})
    s = np.geomspace(0.15, 150, 1000)
    ax.semilogy(s, np.abs(G(s)), "b-", lw=1.5, label="G(s), eq. 15")
    style = {"icosahedral": ("o", "r"), "tetrahedral": ("s", "darkorange"), "latlong": ("^", "g")}
    for (tess, res), rows in results.items():
        m, col = style[tess]
        fine = res == "fine"
        ax.semilogy([2 / r ** 2 for r, *_ in rows], [g for _, g, *_ in rows], m, color=col,
                    mfc="none" if fine else col, ms=8 if fine else 4,
                    label=f"{tess}, {rows[0][3]:,} vertices")
        axd.plot([2 / r ** 2 for r, *_ in rows], [100 * (g / G(2 / r ** 2) - 1) for r, g, *_ in rows],
                 m + ("--" if fine else "-"), color=col, mfc="none" if fine else col, ms=6 if fine else 4, lw=0.8)
    axd.axhline(0, color="b", lw=1)
    axd.set_ylabel("$r_O/r_I$ / G − 1  (%)")
    axd.grid(True, which="both", alpha=0.3)
    axd.set_xlabel("s = 2 / r$^2$  (sphere radius r = 3 ... 0.15)")
    ax.set_xscale("log")
    ax.set_ylabel("measured radius ratio $r_O / r_I$")
    ax.set_title("Fig. 6 filter: s1 = 10, s2 = 25, G0 = 1, G1 = 30, Ginf = 0", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "fig6.png"), dpi=100)

    L = ["# Fig. 6 reproduced: sphere radius ratio against G(2/r²)\n",
         "Filter: GeoFilter: Custom, s1 = 10, s2 = 25, G0 = 1, G1 = 30, "
         "Ginf = 0, useSelection off, through meshlabserver. Measured: r_O/r_I, the mean distance of the vertices to "
         "their centroid after over before (the paper's measure); deviation = measured / G(2/r²) − 1. Per-vertex: the "
         "largest |r_O,i / r_I,i / G − 1| over the vertices, i.e. how unevenly the sphere was scaled. "
         "Tessellations: icosahedral = MeshLab's Sphere (subdivided 4 or 2 times); tetrahedral = 5 or 3 "
         "1-to-4 splits, projected after each; lat/long = 31 rings × 64 or 7 rings × 16, plus 2 poles.\n",
         "| tessellation | vertices | largest \\|deviation\\| of r_O/r_I | at r | median | largest per-vertex deviation | sign |",
         "|---|---:|---:|---:|---:|---:|---|"]
    for (tess, res), rows in results.items():
        dev = [(g / G(2 / r ** 2) - 1, r) for r, g, *_ in rows]
        worst = max(dev, key=lambda x: abs(x[0]))
        signs = "all positive" if all(row[2] > 0 for row in rows) else "SOME NEGATIVE"
        L.append(f"| {tess} | {rows[0][3]:,} | {100 * worst[0]:+.2f} % | {worst[1]:.3f} | "
                 f"{100 * np.median([abs(d) for d, _ in dev]):.2f} % | {100 * max(row[4] for row in rows):.1f} % | {signs} |")
    L += ["", "Measured r_O/r_I (deviation from G):\n",
          "| r | s = 2/r² | G(s) | " + " | ".join(f"{t} {rows[0][3]}" for (t, _), rows in results.items()) + " |",
          "|---:|---:|---:|" + "---:|" * len(results)]
    for i, r in enumerate(RADII):
        g = G(2 / r ** 2)
        L.append(f"| {r:.3f} | {2 / r ** 2:.2f} | {g:.4g} | " +
                 " | ".join(f"{rows[i][1]:.4g} ({100 * (rows[i][1] / g - 1):+.1f} %)" for rows in results.values()) + " |")
    L += ["", "![Fig. 6 reproduced](images/fig6.png)"]
    with open(os.path.join(args.out, "fig6.md"), "w") as out:
        out.write("\n".join(L) + "\n")
    print(f"wrote {args.out}/fig6.png and fig6.md")
    pages.write_page("fig6", "\n".join(L), {"fig6.png": os.path.join(args.out, "fig6.png")})


if __name__ == "__main__":
    main()
