"""GeoFilter Lowpass against MeshLab's Taubin, cotangent Laplacian and HC Laplacian smoothing.

    experiments/run compare_taubin [--out results/taubin] [--workdir DIR] [--keep] [--meshes bunny00,...]

For bunny00, diplodocus and fandisk_large, scaled to unit bounding-box diagonal: Gaussian noise
along the vertex normals (standard deviation 0.1%, 0.25%, 0.5% of the diagonal, fixed seeds),
then every method through the private prefix's meshlabserver (under Xvfb), each compared with
the clean mesh:
  - GeoFilter Lowpass by the rule below, plus the best r/h of a small sweep;
  - Taubin Smooth (lambda 0.5, mu -0.53), Laplacian Smooth (cotangent weights) and
    HC Laplacian Smooth, each at the best step count of a sweep.
Writes results/taubin/comparison.md (RMS and max vertex distance, RMS distance to the clean
surface, volume change, mean face-normal error, time), sweeps.json (every sweep point) and
<mesh>.png (noisy, GeoFilter, Taubin, clean at 0.25 % noise). About 5-8 minutes on 2 shared
cores; needs a built prefix (scripts/build.sh).

How GeoFilter's cutoff is chosen (the "rule"): independent per-vertex noise lives at the
mesh's sampling scale, the mean edge length h; a feature worth keeping is a few edges wide.
Take r = 3 h as the smallest feature radius to keep and s1 = 2/r^2 (a sphere-like feature,
paper section 6), s2 = 2 s1, G0 = 1, G1 = 1.1, Ginf = 0: the steepest (40 dB/decade) lowpass,
G(s) ~ 11 (s1/s)^2 above s1. By Weyl's law a mesh of n vertices has about A s / (4 pi) modes
below s, so only ~1.5 % of the noise modes lie below this s1. The rule uses only the noisy mesh.
The "best" rows (GeoFilter's r/h sweep, every smoother's step count) are picked with the clean
mesh, i.e. by an oracle no user has: they show each method's ceiling, not what a user gets.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from geofilter_experiments import common as c
from geofilter_experiments import pages
from geofilter_experiments.common import h

MESHES = [  # name, renderer "up" axis, view (azimuth, elevation)
    ("bunny00", "y", "0,15"),
    ("diplodocus", "y", "0,15"),
    ("fandisk_large", "z", "30,20"),
]
LEVELS = [0.001, 0.0025, 0.005]  # noise standard deviation / bounding-box diagonal
RENDER_LEVEL = 0.0025
SEED = 20050101
RULE_K = 3.0  # GeoFilter rule: r = RULE_K * mean edge length
GF_SWEEP_K = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0]
# Cumulative counts: one meshlabserver run walks the whole list, saving a layer at each.
TAUBIN_STEPS = [1, 2, 3, 5, 8, 12, 20, 30, 50, 80, 120, 200]
LAPLACIAN_STEPS = [1, 2, 3, 4, 6, 8, 12, 16]
HC_STEPS = [1, 2, 3, 4, 6, 8, 12, 16, 24]
TIMING_REPEATS = 2  # the minimum of repeated wall times, against the other jobs on the machine




def measures(v, f, clean_v, clean_fn, clean_vol):
    d = np.linalg.norm(v - clean_v, axis=1)
    fn = c.face_normals(v, f)
    ang = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", fn, clean_fn), -1, 1)))
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "max": float(d.max()), "flipped": int(np.sum(ang > 90)),
            "dvol": float(100 * (c.signed_volume(v, f) - clean_vol) / clean_vol), "nerr": float(ang.mean())}


def chain(step_for, counts):
    """Script steps applying a smoother cumulatively, a layer per count: layer i = counts[i]."""
    steps, done = [c.select_none()], 0
    for i, n in enumerate(counts):
        if i:
            steps.append(c.duplicate_layer())
        steps += step_for(n - done)
        done = n
    return steps


def geofilter_step(s1):
    return c.geofilter("GeoFilter: Lowpass", s1=s1, s2=2 * s1, G0=1.0, G1=1.1, Ginf=0.0, useSelection=False)


METHODS = {  # key: (label, script steps for a setting)
    "taubin": ("Taubin λ=0.5 μ=-0.53", lambda n: [c.taubin(n)]),
    "laplacian": ("Laplacian (cotangent)", lambda n: [c.laplacian(n, cotangent=True)]),
    "hc": ("HC Laplacian", lambda n: [c.hc_laplacian()] * n),
}
COUNTS = {"taubin": TAUBIN_STEPS, "laplacian": LAPLACIAN_STEPS, "hc": HC_STEPS}


def timed(workdir, steps, noisy, name):
    """Best-of-TIMING_REPEATS wall time of a meshlabserver run (load, script, save)."""
    out = os.path.join(workdir, name + ".ply")
    best, log = None, None
    for _ in range(TIMING_REPEATS):
        r, wall = c.run(workdir, steps, inputs=[noisy], outputs=[(out, None)], name=name)
        if best is None or wall < best:
            best, log = wall, r
    return best, log


def run_case(work, name, level, clean_ply, clean_v, f, clean_fn, clean_vol, rng):
    d = os.path.join(work, f"{name}-{level:g}")
    os.makedirs(d, exist_ok=True)
    clean_area_n = c.vertex_normals(clean_v, f)
    # Noise along the clean normals, like a scanner's depth error; tangential noise would barely
    # change the shape and would flatter every method.
    noisy_v = clean_v + (level * rng.standard_normal(len(clean_v)))[:, None] * clean_area_n
    noisy = os.path.join(d, "noisy.ply")
    noisy_v = c.write_and_reload(noisy, noisy_v, f)
    h_noisy = c.mean_edge_length(noisy_v, f)  # what a user measures: the rule sees only the noisy mesh
    m = lambda v: measures(v, f, clean_v, clean_fn, clean_vol)
    rows = {"noisy": dict(m(noisy_v), setting="input", time=None)}
    sweeps = {}

    # GeoFilter: r/h sweep in one run, each on a copy of the noisy layer 0; then the rule's
    # filter on a copy of the clean layer 1, to separate the filter's own bias from leftover noise.
    steps = [c.select_none()]
    s1s = [2.0 / (k * h_noisy) ** 2 for k in GF_SWEEP_K]
    for s1 in s1s:
        steps += [c.current_layer(0), c.duplicate_layer(), geofilter_step(s1)]
    steps += [c.current_layer(1), c.duplicate_layer(), geofilter_step(s1s[GF_SWEEP_K.index(RULE_K)])]
    outs_gf = [os.path.join(d, f"gf{i}.ply") for i in range(len(s1s))]
    bias_ply = os.path.join(d, "gf-clean.ply")
    r, _ = c.run(d, steps, inputs=[noisy, clean_ply],
                 outputs=[(o, i + 2) for i, o in enumerate(outs_gf)] + [(bias_ply, len(s1s) + 2)], name="gf-sweep")
    logged = c.geofilter_times(r)
    sweep = []
    for k, s1, o, t in zip(GF_SWEEP_K, s1s, outs_gf, logged):
        sweep.append(dict(m(h.read_ply(o).vertices), k=k, s1=s1, logged=t))
    sweeps["geofilter"] = sweep
    rule = next(x for x in sweep if x["k"] == RULE_K)
    best_gf = min(sweep, key=lambda x: x["rms"])

    # The smoothers: one cumulative run each.
    best = {}
    for key, (label, step_for) in METHODS.items():
        counts = COUNTS[key]
        outs = [os.path.join(d, f"{key}{n}.ply") for n in counts]
        c.run(d, chain(step_for, counts), inputs=[noisy], outputs=[(o, i) for i, o in enumerate(outs)],
              name=key + "-sweep")
        sweeps[key] = [dict(m(h.read_ply(o).vertices), steps=n) for n, o in zip(counts, outs)]
        best[key] = min(sweeps[key], key=lambda x: x["rms"])
        if best[key]["steps"] == counts[-1]:
            print(f"  warning: {key} best at the sweep's end ({counts[-1]} steps)", file=sys.stderr)
    if best_gf["k"] in (GF_SWEEP_K[0], GF_SWEEP_K[-1]):
        print(f"  warning: GeoFilter best at the sweep's end (r = {best_gf['k']} h)", file=sys.stderr)

    # Timing: wall time of a run with the chosen setting minus a run that only loads and saves.
    base, _ = timed(d, [c.select_none()], noisy, "t-baseline")
    t_rule, log_rule = timed(d, [c.select_none(), geofilter_step(rule["s1"])], noisy, "t-gf-rule")
    rows["gf_rule"] = dict(rule, setting=f"r = {RULE_K:g} h, s1 = {rule['s1']:.0f}", time=t_rule - base,
                           logged=c.geofilter_times(log_rule)[0])
    if best_gf is rule:
        rows["gf_best"] = dict(rows["gf_rule"])
    else:
        t_best, log_best = timed(d, [c.select_none(), geofilter_step(best_gf["s1"])], noisy, "t-gf-best")
        rows["gf_best"] = dict(best_gf, time=t_best - base, logged=c.geofilter_times(log_best)[0])
    rows["gf_best"]["setting"] = f"r = {best_gf['k']:g} h, s1 = {best_gf['s1']:.0f}"
    rows["gf_clean"] = dict(m(h.read_ply(bias_ply).vertices), setting=rows["gf_rule"]["setting"], time=None)
    for key, (label, step_for) in METHODS.items():
        t, _ = timed(d, [c.select_none()] + step_for(best[key]["steps"]), noisy, "t-" + key)
        rows[key] = dict(best[key], setting=f"{best[key]['steps']} " + ("applications" if key == "hc" else "steps"),
                         time=t - base)
    # Vertex-to-vertex distance also counts tangential drift, which leaves the surface where it
    # was; the distance to the clean surface does not. Costly, so only for the reported rows.
    files = {"noisy": noisy, "gf_clean": bias_ply, "gf_rule": outs_gf[GF_SWEEP_K.index(RULE_K)],
             "gf_best": outs_gf[GF_SWEEP_K.index(best_gf["k"])]}
    files.update({key: os.path.join(d, f"{key}{best[key]['steps']}.ply") for key in METHODS})
    for key, path in files.items():
        ds = c.distance_to_surface(h.read_ply(path).vertices, clean_v, f)
        rows[key]["srms"] = float(np.sqrt(np.mean(ds ** 2)))
    case = {"mesh": name, "level": level, "h_noisy": h_noisy, "baseline_wall": base, "rows": rows,
            "sweeps": sweeps, "dir": d}
    return case


ROW_LABELS = [("noisy", "noisy input"), ("gf_rule", "GeoFilter Lowpass, rule"),
              ("gf_best", "GeoFilter Lowpass, best r (oracle)"), ("taubin", "Taubin λ=0.5 μ=-0.53, best steps (oracle)"),
              ("laplacian", "Laplacian cotangent, best steps (oracle)"), ("hc", "HC Laplacian, best count (oracle)"),
              ("gf_clean", "*GeoFilter rule on the clean mesh (its bias)*")]


def fmt_time(row):
    if row.get("time") is None:
        return "–"
    s = f"{max(row['time'], 0):.2f}"
    if row.get("logged") is not None:
        s += f" ({row['logged']:.2f})"
    return s


def write_markdown(path, cases, mesh_info, total):
    L = []
    L.append("# GeoFilter Lowpass against MeshLab's smoothers\n")
    L.append(f"Everything through meshlabserver 2020.09 and the plugin of this tree; total run {total:.0f} s.\n")
    L.append("- Meshes scaled to unit bounding-box diagonal and centred; **all three are closed** "
             "(every edge has two faces), so the signed volume is the enclosed volume.")
    L.append("- Noise: Gaussian displacement along the area-weighted vertex normals, standard deviation "
             "σ = 0.1 %, 0.25 %, 0.5 % of the diagonal, fixed seed.")
    L.append("- Distances are **vertex to vertex** against the clean mesh (every filter keeps the "
             "connectivity and vertex order), in units of 10⁻³ of the diagonal; *RMS to surface* is the "
             "RMS distance from the vertices to the clean surface (point to triangle), which does not count "
             "tangential sliding of vertices along the surface. ΔV: signed-volume change "
             "against the clean mesh, %. Normal error: mean angle between face normals and the clean "
             "mesh's, degrees (unweighted mean over faces). Flipped: faces whose normal is more than 90° "
             "off the clean one (folds). The last row per noise level applies the rule's filter to the "
             "*clean* mesh: the error GeoFilter adds by itself.")
    L.append(f"- GeoFilter rule: r = {RULE_K:g} × mean edge length h of the noisy mesh, s1 = 2/r², s2 = 2 s1, "
             "G0 = 1, G1 = 1.1, Ginf = 0 (see the script's docstring for why). "
             f"Sweep: r/h ∈ {GF_SWEEP_K}.")
    L.append(f"- Sweeps (best = smallest RMS distance to the clean mesh, i.e. chosen with the answer known): "
             f"Taubin steps {TAUBIN_STEPS}; Laplacian (cotangent, VCG's full-step averaging) steps "
             f"{LAPLACIAN_STEPS}; HC Laplacian applications {HC_STEPS} (the 2020.09 filter does one "
             "iteration per application, its reference being the mesh at that application).")
    L.append("- Time: meshlabserver wall time with the filter minus a run that only loads and saves the "
             f"same mesh (best of {TIMING_REPEATS} each; on 2 shared cores differences below ~0.3 s are noise, and "
             "negative differences are shown as 0); in parentheses GeoFilter's "
             "own logged solver time (assembly + factorisation + solve).\n")
    L.append("| mesh | vertices | h (mean edge) | closed |")
    L.append("|---|---:|---:|---|")
    for name, info in mesh_info.items():
        L.append(f"| {name} | {info['n']:,} | {info['h']:.4f} | {'yes' if info['closed'] else 'no'} |")
    L.append("")
    for name in mesh_info:
        L.append(f"## {name}\n")
        L.append("| σ | method | setting | RMS | max | RMS to surface | ΔV % | normal err ° | flipped | time s |")
        L.append("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
        for case in [x for x in cases if x["mesh"] == name]:
            for key, label in ROW_LABELS:
                r = case["rows"][key]
                L.append(f"| {100 * case['level']:g} % | {label} | {r['setting']} | {1e3 * r['rms']:.3f} | "
                         f"{1e3 * r['max']:.2f} | {1e3 * r['srms']:.3f} | {r['dvol']:+.3f} | {r['nerr']:.2f} | {r['flipped']} | {fmt_time(r)} |")
        L.append("")
    L.append("## Who wins\n")
    L.append("Best of the five denoised rows per criterion (the GeoFilter rule row is the only one chosen "
             "without the clean mesh).\n")
    L.append("| mesh | σ | RMS (vertex) | RMS to surface | normal error | GeoFilter rule vs best smoother, RMS to surface |")
    L.append("|---|---|---|---|---|---|")
    short = {"gf_rule": "GeoFilter rule", "gf_best": "GeoFilter best r", "taubin": "Taubin",
             "laplacian": "Laplacian cot", "hc": "HC Laplacian"}
    for case in cases:
        rows = {k: v for k, v in case["rows"].items() if k not in ("noisy", "gf_clean")}
        win = [min(rows, key=lambda k: rows[k][m]) for m in ("rms", "srms", "nerr")]
        sm = min(("taubin", "laplacian", "hc"), key=lambda k: rows[k]["srms"])
        L.append(f"| {case['mesh']} | {100 * case['level']:g} % | " + " | ".join(short[w] for w in win) +
                 f" | {1e3 * rows['gf_rule']['srms']:.3f} vs {1e3 * rows[sm]['srms']:.3f} ({short[sm]}) |")
    L.append("")
    with open(path, "w") as out:
        out.write("\n".join(L))
    return "\n".join(L)


def render(out_png, case, clean_ply, up, view):
    rows = case["rows"]
    d = case["dir"]
    gf_i = GF_SWEEP_K.index(RULE_K)
    files = [f"{d}/noisy.ply=noisy (σ = {100 * case['level']:g} % diag)",
             f"{d}/gf{gf_i}.ply=GeoFilter Lowpass, {rows['gf_rule']['setting']}",
             f"{d}/taubin{rows['taubin']['steps']}.ply=Taubin, {rows['taubin']['steps']} steps (best)",
             f"{clean_ply}=clean"]
    subprocess.run([sys.executable, "-m", "geofilter_experiments.render_meshes", out_png, "--up", up, "--view", view]
                   + files, check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "taubin"))
    ap.add_argument("--workdir", help="intermediate meshes (default: a temporary folder, removed)")
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    ap.add_argument("--meshes", default=",".join(m[0] for m in MESHES))
    ap.add_argument("--levels", default=",".join(str(x) for x in LEVELS), help="noise levels (fractions of the diagonal)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    work = args.workdir or tempfile.mkdtemp(prefix="compare-taubin-")
    os.makedirs(work, exist_ok=True)
    t0 = time.perf_counter()
    cases, mesh_info = [], {}
    chosen = [m for m in MESHES if m[0] in args.meshes.split(",")]
    for name, up, view in chosen:
        mi = [m[0] for m in MESHES].index(name)  # seeds do not depend on which meshes are run
        v, f = c.load_normalised(name)
        clean_ply = os.path.join(work, name + "-clean.ply")
        clean_v = c.write_and_reload(clean_ply, v, f)
        clean_fn = c.face_normals(clean_v, f)
        clean_vol = c.signed_volume(clean_v, f)
        mesh_info[name] = {"n": len(v), "h": c.mean_edge_length(clean_v, f), "closed": c.is_closed(f)}
        for level in (float(x) for x in args.levels.split(",")):
            print(f"{name}, noise {100 * level:g} % ...", flush=True)
            rng = np.random.default_rng([SEED, mi, round(level * 1e6)])
            case = run_case(work, name, level, clean_ply, clean_v, f, clean_fn, clean_vol, rng)
            cases.append(case)
            rr = case["rows"]
            print("  RMS x1e-3: " + ", ".join(f"{k} {1e3 * rr[k]['rms']:.3f}" for k, _ in ROW_LABELS), flush=True)
            if level == RENDER_LEVEL:
                render(os.path.join(args.out, f"{name}.png"), case, clean_ply, up, view)
    total = time.perf_counter() - t0
    with open(os.path.join(args.out, "sweeps.json"), "w") as out:
        json.dump({"meshes": mesh_info, "cases": [{k: v for k, v in x.items() if k != "dir"} for x in cases]},
                  out, indent=1)
    text = write_markdown(os.path.join(args.out, "comparison.md"), cases, mesh_info, total)
    print(f"wrote {args.out}/comparison.md, sweeps.json and PNGs; {total:.0f} s")
    if pages.partial_run(ap, args):
        print("a partial run: docs/results/taubin.md left as it was")
    else:
        images = {f"taubin-{name}.png": os.path.join(args.out, f"{name}.png") for name, _, _ in chosen}
        text += "\n## Renders\n\nNoisy, the GeoFilter rule, Taubin at its best step count, clean, at σ = " \
                f"{100 * RENDER_LEVEL:g} %.\n\n" + "\n".join(f"![{name}](images/{file})" for file, name in
                                                 zip(images, (m[0] for m in chosen))) + "\n"
        pages.write_page("taubin", text, images)
    if not args.keep and not args.workdir:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
