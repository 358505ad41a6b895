"""The paper's Figs. 1, 9, 10, 11 and 12: its parameter sets applied through meshlabserver.

    experiments/run reproduce_figures [--out results/figures] [--only fig1,fig9,...]

Each figure: the input, the GeoFilter result(s) (GeoFilter: Custom, useSelection off) and the
designed |G(s)| on log-log axes with s1 and s2 marked, flipped (G < 0) bands dashed.
The meshes are used as they are (no rescaling): the paper's frequencies are in the paper's
model units, which we do not know; ours are roughly unit-sized (bounding-box diagonal: bunny
1.60, diplodocus 1.41, elephant 1.37, man 1.13). So a given s1 is a feature of the same
absolute radius r = sqrt(2/s1) here as there, but not necessarily the same feature.
There is no horse here: Fig. 11's parameters go to the elephant.
Writes figN.png and figures.md (GeoFilter's own log: solver time, max |G|, warnings).
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
from geofilter_experiments.render_meshes import draw, view_matrix  # noqa: E402


def P(s1, s2, G0, G1, Ginf):
    return dict(s1=s1, s2=s2, G0=G0, G1=G1, Ginf=Ginf)


FIGURES = {  # name: (mesh, up, view, caption, [(label, params)])  -- docs/paper-notes.md §9
    "fig1": ("bunny00", "y", "0,10", "Fig. 1: grow the ear (bunny)",
             [("Ginf = 0: bumps smoothed", P(20, 25, 1, 2, 0)), ("Ginf = 0.9: bumps kept", P(20, 25, 1, 2, 0.9))]),
    "fig9": ("diplodocus", "y", "0,15", "Fig. 9: back-bone band, s1 = 630 (diplodocus)",
             [("band exaggeration", P(630, 1260, 1, 3, 0.9)), ("band stop (notch)", P(630, 1260, 1, 0.01, 1.1))]),
    "fig10": ("diplodocus", "y", "0,15", "Fig. 10: leg band exaggeration, s1 = 25 (diplodocus)",
              [("Ginf = 0", P(25, 60, 1, 3, 0)), ("Ginf = 0.9", P(25, 60, 1, 3, 0.9))]),
    "fig11": ("refined_elephant", "y", "180,10", "Fig. 11: exaggerate legs, s1 = 60 (elephant; the paper's horse)",
              [("exaggeration", P(60, 120, 1, 2, 0.9))]),
    "fig12": ("man", "z", "0,10", "Fig. 12: human model",
              [("lowpass", P(25, 50, 1, 1.1, 0)), ("older", P(200, 1000, 0.5, 1.1, 0)),
               ("cartoon", P(25, 400, 0.5, 1.1, 0.5))]),
}


def apply(workdir, mesh, designs, tag):
    """All of a figure's filters in one meshlabserver run, each on a copy of the input (layer 0)."""
    steps, outputs = [c.select_none()], []
    for i, (_, p) in enumerate(designs):
        steps += [c.current_layer(0), c.duplicate_layer(), c.geofilter("GeoFilter: Custom", useSelection=False, **p)]
        outputs.append((os.path.join(workdir, f"{tag}-{i}.ply"), i + 1))
    r, wall = c.run(workdir, steps, inputs=[os.path.join(c.MESHES_DIR, mesh + ".off")], outputs=outputs, name=tag)
    return [h.read_ply(o).vertices for o, _ in outputs], r, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "figures"))
    ap.add_argument("--only", default=",".join(FIGURES))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    md = ["# Figs. 1, 9-12 reproduced\n",
          "The paper's parameter sets (docs/paper-notes.md §9) through "
          "meshlabserver, GeoFilter: Custom with useSelection off, on our meshes *unscaled* (the paper's "
          "model units are unknown). Log lines are GeoFilter's own.\n"]
    with tempfile.TemporaryDirectory(prefix="figures-") as work:
        for tag in args.only.split(","):
            mesh, up, view, caption, designs = FIGURES[tag]
            v, f = c.read_off(os.path.join(c.MESHES_DIR, mesh + ".off"))
            outs, run, wall = apply(work, mesh, designs, tag)
            edge = c.mean_edge_length(v, f)
            diag = c.bbox_diagonal(v)
            rot = view_matrix(*(float(x) for x in view.split(",")), up)
            n = len(designs) + 1
            fig = plt.figure(figsize=(3.4 * n + 4.4, 4.9))
            gs = fig.add_gridspec(1, n + 1, width_ratios=[1] * n + [1.35])
            draw(fig.add_subplot(gs[0]), v, f, rot, f"input: {mesh} ({len(v):,} v.)")
            for i, ((label, p), vo) in enumerate(zip(designs, outs)):
                scale = c.bbox_diagonal(vo) / diag
                extra = f"\nsize ×{scale:.2f}, shown zoomed" if abs(scale - 1) > 0.15 else ""
                # r: the radius of the sphere-like feature at s1, in this mesh's units.
                draw(fig.add_subplot(gs[i + 1]), vo, f, rot,
                     f"{label}\ns1={p['s1']:g} (r={np.sqrt(2 / p['s1']):.2g}) s2={p['s2']:g}\n"
                     f"G0={p['G0']:g} G1={p['G1']:g} Ginf={p['Ginf']:g}{extra}")
            ax = fig.add_subplot(gs[n])
            lo = min(min(p["s1"], p["s2"]) for _, p in designs) / 30
            sh = 2 / edge ** 2  # a sphere of one edge's radius: about the finest mode the mesh holds
            smax = max(sh * 2, max(max(p["s1"], p["s2"]) for _, p in designs) * 30)
            c.plot_gains(ax, designs, (lo, smax), marks=[(sh, "2/h² (h = mean edge)"),
                                                          (2 / (diag / 2) ** 2, "2/R², R = half diagonal")])
            ax.set_title("designed gain (eq. 15)", fontsize=9)
            fig.suptitle(caption, fontsize=11)
            fig.tight_layout(rect=(0, 0, 1, 0.93))  # room for the suptitle
            png = os.path.join(args.out, tag + ".png")
            fig.savefig(png, dpi=90)
            plt.close(fig)
            print(f"wrote {png}", flush=True)
            md.append(f"## {caption}\n\n![{tag}](images/{tag}.png)\n")
            md.append(f"{mesh}: {len(v):,} vertices, bounding-box diagonal {diag:.3f}, mean edge h = {edge:.4f}; "
                      f"meshlabserver wall time {wall:.1f} s for all {len(designs)} filter(s).\n")
            seen = []
            for line in run.log:
                if line.startswith("GeoFilter") and ("peak" in line or "time" in line or "warning" in line.lower()) \
                        and line not in seen:
                    seen.append(line)
            md += ["```"] + seen + ["```", ""]
    with open(os.path.join(args.out, "figures.md"), "w") as out:
        out.write("\n".join(md))
    print(f"wrote {args.out}/figures.md")
    if pages.partial_run(ap, args):
        print("a partial run: docs/results/figures.md left as it was")
    else:
        pages.write_page("figures", "\n".join(md), {f"{tag}.png": os.path.join(args.out, f"{tag}.png") for tag in FIGURES})


if __name__ == "__main__":
    main()
