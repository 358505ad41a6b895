"""GeoFilter Denoise against MeshLab's smoothers, through meshlabserver.

Two tasks, each with ground truth:
  feature-scale   a sphere / torus with large bumps plus a pattern of small ones (2 size ratios,
                  2 densities) and the five scans below with a synthetic texture of bumps 4 mean
                  edge lengths wide; the truth is the shape without the small bumps. Denoise is
                  driven by ONE selected small bump (Conditional Face Selection around its
                  centre, as a user would select it). Each case also reports how much of the
                  truth itself Denoise's separating lowpass removes (its own detail at the
                  bumps' scale), as a share of the bumps' height.
  sampling noise  bunny00, diplodocus, fandisk_large, refined_elephant, man (meshes/, unit
                  bounding-box diagonal) with Gaussian noise of sigma = 0.1, 0.3, 0.5 x the mean edge
                  length along the normals, and in random directions (each mesh at 0.3, bunny00
                  at 0.1 and 0.5 too); Denoise with nothing selected.
Rows: Denoise untuned; GeoFilter's best over a sweep; MeshLab Taubin, HC Laplacian, Laplacian
(cotangent) and TwoStep at their default parameters and at their best over a sweep. Every "best"
is chosen against the truth, which no user has (an oracle). Metrics: RMS vertex distance, mean
point-to-surface distance, mean face-normal error, volume change, folded faces (normal more than
90 degrees off the truth's), time (wall time of one meshlabserver run minus one load-and-save run, on a shared machine:
indicative only).

Writes <out>/denoise.md and <out>/denoise.json. Usage:
    experiments/run compare_denoise [--out results/denoise] [--only feature|noise]
"""
import argparse
import json
import os
import shutil
import sys
import tempfile
import time

import numpy as np

from geofilter_experiments import common as c
from geofilter_experiments import pages
from geofilter_experiments.common import h
from shapes import icosphere  # tests/support, on the path through experiments/run

P = h.Param
SEED = 20260101

# MeshLab 2020.09 defaults (filter_unsharp): Taubin 10 steps, Laplacian 3, HC one application,
# TwoStep 3 steps (normalThr 60, 20 normal and 20 fitting steps).
SWEEP = {
    "taubin": [1, 2, 3, 5, 10, 20, 30, 50, 80, 120, 200],
    "laplacian": [1, 2, 3, 4, 6, 8, 12, 16, 24],
    "hc": [1, 2, 3, 4, 6, 8, 12, 16, 24],
    "twostep": [1, 2, 3, 5, 10, 20],
}
DEFAULT = {"taubin": 10, "laplacian": 3, "hc": 1, "twostep": 3}
LABEL = {"taubin": "Taubin", "laplacian": "Laplacian (cot)", "hc": "HC Laplacian", "twostep": "TwoStep"}


def two_step(steps):
    return h.Step("TwoStep Smooth", [(P("stepSmoothNum", "RichInt", 3), steps), (P("normalThr", "RichFloat", 60.0), 60.0),
                                     (P("stepNormalNum", "RichInt", 20), 20), (P("stepFitNum", "RichInt", 20), 20),
                                     (P("Selected", "RichBool", False), False)])


STEP_FOR = {
    "taubin": lambda n: [c.taubin(n)],
    "laplacian": lambda n: [c.laplacian(n, cotangent=True)],
    "hc": lambda n: [c.hc_laplacian()] * n,
    "twostep": lambda n: [two_step(n)],
}


def chain(key, counts):
    """One run applying a smoother cumulatively; layer i holds counts[i] steps."""
    steps, done = [c.select_none()], 0
    for i, n in enumerate(counts):
        if i:
            steps.append(c.duplicate_layer())
        steps += STEP_FOR[key](n - done)
        done = n
    return steps


# ---------------------------------------------------------------------------------------------
# Procedural meshes

def torus(rings, segments, R, r):
    u = 2 * np.pi * np.arange(rings) / rings
    w = 2 * np.pi * np.arange(segments) / segments
    uu, ww = np.meshgrid(u, w, indexing="ij")
    v = np.stack([(R + r * np.cos(ww)) * np.cos(uu), (R + r * np.cos(ww)) * np.sin(uu), r * np.sin(ww)], -1).reshape(-1, 3)
    f = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            cc, d = ((i + 1) % rings) * segments + j, ((i + 1) % rings) * segments + (j + 1) % segments
            f += [[a, cc, b], [b, cc, d]]
    return v, np.array(f)


def add_bumps(v, n, centres, radius, height):
    """Gaussian bumps height * exp(-(d/radius)^2) along the normals n (d: distance to the centre)."""
    out = v.copy()
    for ctr in centres:
        d2 = np.sum((v - ctr) ** 2, axis=1)
        near = d2 < (4 * radius) ** 2
        out[near] += (height * np.exp(-d2[near] / radius ** 2))[:, None] * n[near]
    return out


def spread(v, count, min_dist, rng):
    """Indices of `count` vertices at least min_dist apart."""
    chosen = []
    for i in rng.permutation(len(v)):
        if any(np.linalg.norm(v[i] - v[j]) < min_dist for j in chosen):
            continue
        chosen.append(i)
        if len(chosen) == count:
            break
    return np.array(chosen)


def feature_cases():
    """(name, truth v, bumpy v, f, small-bump radius, centre of the bump to select)."""
    cases = []
    sv, sf = icosphere(6)  # 40,962 vertices, h = 0.019
    sn = sv.copy()
    # Sparse patterns first: a partial run then covers both size ratios.
    for density, (ratio, rs) in ((150, ("8", 0.05)), (150, ("5", 0.08)), (300, ("8", 0.05)), (300, ("5", 0.08))):
        rng = np.random.default_rng([SEED, int(rs * 1000), density])
        truth = add_bumps(sv, sn, sv[spread(sv, 6, 1.0, rng)], 0.4, 0.12)
        # Small bumps may not overlap each other much; at 300 the 0.08 ones cover the sphere densely.
        small = spread(truth, density, 2.0 * rs if density == 150 else 1.6 * rs, rng)
        bumpy = add_bumps(truth, c.vertex_normals(truth, sf), truth[small], rs, 0.24 * rs)
        # The bump to select is centred on the bumpy surface, where a user sees it.
        cases.append((f"sphere r_large/r_small={ratio} n={len(small)}", truth, bumpy, sf, rs, bumpy[small[0]]))
    tv, tf = torus(240, 96, 1.0, 0.4)  # 23,040 vertices
    core = tv.copy()
    core[:, 2] = 0
    core[:, :2] *= (1.0 / np.linalg.norm(core[:, :2], axis=1))[:, None]
    tn = tv - core
    tn /= np.linalg.norm(tn, axis=1)[:, None]
    rng = np.random.default_rng([SEED, 7])
    truth = add_bumps(tv, tn, tv[spread(tv, 5, 1.0, rng)], 0.3, 0.08)
    small = spread(truth, 200, 0.1, rng)
    bumpy = add_bumps(truth, c.vertex_normals(truth, tf), truth[small], 0.04, 0.01)
    cases.insert(2, ("torus r_large/r_small=7.5 n=200", truth, bumpy, tf, 0.04, bumpy[small[0]]))
    # The scans with a texture of bumps: bunny00 among the procedural cases, the other scans
    # after them (so a partial run covers one scan).
    for mesh in NOISE_MESHES:
        name, bv, bumpy, bf, rs, small = scan_texture_case(mesh)
        case = (name, bv, bumpy, bf, rs, bumpy[small[0]])
        if mesh == "bunny00":
            cases.insert(3, case)
        else:
            cases.append(case)
    return cases


def scan_texture_case(mesh, radius_in_edges=4.0):
    """A scan of meshes/ with a texture of Gaussian bumps (4 mean edge lengths wide in the
    comparison), 0.25 x that high, at least 2.5 widths apart: (name, truth v, bumpy v, f, bump
    radius, bump centre indices)."""
    bv, bf = c.load_normalised(mesh)
    hb = c.mean_edge_length(bv, bf)
    rng = np.random.default_rng([SEED, 11] if mesh == "bunny00" else [SEED, 11, NOISE_MESHES.index(mesh)])
    rs = radius_in_edges * hb
    small = spread(bv, 400, 2.5 * rs, rng)
    bumpy = add_bumps(bv, c.vertex_normals(bv, bf), bv[small], rs, 0.25 * rs)
    return f"{mesh} texture r={rs:.3f} n={len(small)}", bv, bumpy, bf, rs, small


def own_detail(d, truth_file, truth_v, f, denoise_row, height):
    """How much of the truth itself the lowpass Denoise separated the bumps with removes: the
    median |(truth - lowpass(truth)) . n| as a share of the bumps' height. Where it is
    comparable to 1, the surface's own detail at the bumps' scale is as large as the bumps."""
    import re
    sc = re.search(r"cutoff sc = ([0-9.eE+-]+)", denoise_row["setting"])
    if not sc:
        return None
    out = os.path.join(d, "truth-lowpass.ply")
    c.run(d, [butterworth_step(float(sc.group(1)), 4, 1)], inputs=[truth_file], outputs=[(out, None)], name="truth-lowpass")
    lp = h.read_ply(out).vertices
    removed = np.einsum("ij,ij->i", truth_v - lp, c.vertex_normals(lp, f))
    return float(np.median(np.abs(removed)) / height)


# ---------------------------------------------------------------------------------------------
# Measures



def measures(v, f, truth):
    tv, tfn, tvol, closed = truth
    d = np.linalg.norm(v - tv, axis=1)
    fn = c.face_normals(v, f)
    ang = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", fn, tfn), -1, 1)))
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "nerr": float(ang.mean()), "folded": int(np.sum(ang > 90)),
            "dvol": float(100 * (c.signed_volume(v, f) - tvol) / tvol) if closed else None}


def surface_mean(v, truth_v, f):
    return float(c.distance_to_surface(v, truth_v, f).mean())


# ---------------------------------------------------------------------------------------------
# One case

def denoise_step(selected):
    return c.geofilter("GeoFilter: Denoise", useSelection=selected)


def butterworth_step(cutoff, order, op):
    return c.geofilter("GeoFilter: Butterworth Lowpass", cutoff=cutoff, order=order, useSelection=False, operator=op)


def select_bump(centre, radius):
    r2 = radius * radius
    conds = [f"((x{k}-({centre[0]!r}))^2+(y{k}-({centre[1]!r}))^2+(z{k}-({centre[2]!r}))^2 < {r2!r})" for k in range(3)]
    return h.select_faces(" && ".join(conds))


def timed(d, steps, inp, name, base):
    _, wall = c.run(d, steps, inputs=[inp], outputs=[(os.path.join(d, name + "-t.ply"), None)], name=name)
    return max(wall - base, 0.0)


def run_case(d, inp, f, truth, gf_sweep, denoise_steps):
    """gf_sweep: [(label, step)] on copies of layer 0; denoise_steps: the untuned run's script."""
    m = lambda v: measures(v, f, truth)
    rows = {"input": dict(m(h.read_ply(inp).vertices), setting="", time=None, file=inp)}
    _, base = c.run(d, [c.select_none()], inputs=[inp], outputs=[(os.path.join(d, "base.ply"), None)], name="base")

    out = os.path.join(d, "denoise.ply")
    r, wall = c.run(d, denoise_steps, inputs=[inp], outputs=[(out, None)], name="denoise")
    log = [line for line in r.log if "cutoff sc" in line or "design:" in line or "noise model:" in line]
    rows["denoise"] = dict(m(h.read_ply(out).vertices), setting="; ".join(log[-3:]), file=out, time=wall - base)

    steps, outs = [], []
    for i, (label, step) in enumerate(gf_sweep):
        steps += [c.current_layer(0), c.duplicate_layer(), step]
        outs.append((os.path.join(d, f"gf{i}.ply"), i + 1))
    c.run(d, steps, inputs=[inp], outputs=outs, name="gf-sweep")
    sweep = [dict(m(h.read_ply(o).vertices), setting=label, file=o) for (label, _), (o, _) in zip(gf_sweep, outs)]
    rows["gf_best"] = dict(min(sweep, key=lambda x: x["rms"]), time=None)
    sweeps = {"geofilter": sweep}

    for key, counts in SWEEP.items():
        outs = [os.path.join(d, f"{key}{n}.ply") for n in counts]
        if key == "twostep":
            # TwoStep asserts on a duplicated layer (its VF adjacency is not rebuilt): a run per count.
            for n, o in zip(counts, outs):
                c.run(d, [c.select_none()] + STEP_FOR[key](n), inputs=[inp], outputs=[(o, None)], name=f"{key}{n}")
        else:
            c.run(d, chain(key, counts), inputs=[inp], outputs=[(o, i) for i, o in enumerate(outs)], name=key + "-sweep")
        sw = [dict(m(h.read_ply(o).vertices), setting=f"{n} steps", file=o, steps=n) for n, o in zip(counts, outs)]
        sweeps[key] = sw
        dflt = next(x for x in sw if x["steps"] == DEFAULT[key])
        rows[key + "_default"] = dict(dflt, time=timed(d, [c.select_none()] + STEP_FOR[key](DEFAULT[key]), inp,
                                                        "t-" + key, base))
        best = min(sw, key=lambda x: x["rms"])
        if best["steps"] == counts[-1]:
            print(f"  warning: {key} best at the sweep's end", file=sys.stderr)
        rows[key + "_best"] = dict(best, time=None)
    for row in rows.values():
        row["surf"] = surface_mean(h.read_ply(row["file"]).vertices, truth[0], f)
    return rows, sweeps


ROWS = ([("input", "input"), ("denoise", "**GeoFilter Denoise, untuned**"), ("gf_best", "GeoFilter Butterworth, best (oracle)")] +
        [(k + "_default", LABEL[k] + ", default") for k in SWEEP] + [(k + "_best", LABEL[k] + ", best (oracle)") for k in SWEEP])


def short_setting(key, r):
    """The Denoise row's setting is its log lines: keep the cutoff, its origin and the operator."""
    if key != "denoise":
        return r["setting"]
    import re
    text = r["setting"]
    sc = re.search(r"cutoff sc = ([0-9.eE+-]+)", text)
    op = re.search(r"operator ([a-zA-Z ]+?)(?: \(|;|$)", text)
    origin = "selected bump, cutoff radius 2 r" if "selected bump" in text else "nothing selected"
    model = re.search(r"noise model: ([a-z ]+?) \(", text)
    noise = f"; noise {model.group(1)}" if model else ""
    return f"{origin}{noise}; n = 4, sc = {sc.group(1) if sc else '?'}, {op.group(1) if op else '?'}"


def table(case):
    L = ["| method | setting | RMS vertex (1e-3) | mean to surface (1e-3) | normal error (°) | volume | folded | time (s) |",
         "|---|---|---:|---:|---:|---:|---:|---:|"]
    for key, label in ROWS:
        r = case["rows"][key]
        vol = "–" if r["dvol"] is None else f"{r['dvol']:+.3f} %"
        t = "–" if r.get("time") is None else f"{r['time']:.2f}"
        L.append(f"| {label} | {short_setting(key, r)} | {1e3 * r['rms']:.3f} | {1e3 * r['surf']:.3f} | {r['nerr']:.2f} | {vol} | "
                 f"{r['folded']} | {t} |")
    return "\n".join(L)


def floors_feature(rows):
    others = [rows[k] for k in rows if k.endswith("_default") or k.endswith("_best")]
    others = [o for o in others if o is not rows["gf_best"]]
    dn = rows["denoise"]
    return {"rms": all(dn["rms"] < o["rms"] for o in others), "nerr": all(dn["nerr"] < o["nerr"] for o in others),
            "vol": dn["dvol"] is None or abs(dn["dvol"]) <= 0.3}


def floors_noise(rows):
    dn = rows["denoise"]
    return {"rms_vs_hc_lap": dn["rms"] < rows["hc_default"]["rms"] and dn["rms"] < rows["laplacian_default"]["rms"],
            "within10_taubin": dn["rms"] <= 1.1 * rows["taubin_default"]["rms"],
            "beats_taubin": dn["rms"] < rows["taubin_default"]["rms"],
            "vol": dn["dvol"] is None or abs(dn["dvol"]) <= 0.3, "folded": dn["folded"] <= rows["input"]["folded"]}


NOISE_MESHES = ["bunny00", "diplodocus", "fandisk_large", "refined_elephant", "man"]
NOISE_K = [0.1, 0.3, 0.5]
UMBRELLA_CUTOFFS = [0.15, 0.25, 0.35, 0.5, 0.7, 1.0]
COT_K = [0.75, 1.0, 1.5, 2.0]  # cutoff radius in mean edge lengths


def summary(results):
    """One line per case: Denoise against the smoothers' defaults and their best (RMS / normal error)."""
    cell = lambda r: f"{1e3 * r['rms']:.3f} / {r['nerr']:.1f}°"
    L = ["## Summary (RMS vertex distance in 1e-3 of the diagonal / mean normal error)\n",
         "| case | input | **Denoise** (volume, folded) | Taubin default | HC default | Laplacian default | TwoStep default |"
         " best MeshLab smoother (oracle) | GeoFilter best (oracle) |",
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for kind in ("feature", "noise"):
        for case in results[kind]:
            r = case["rows"]
            best_key = min((k + "_best" for k in SWEEP), key=lambda k: r[k]["rms"])
            dn = r["denoise"]
            vol = "–" if dn["dvol"] is None else f"{dn['dvol']:+.2f} %"
            L.append(f"| {case['name']} | {cell(r['input'])} | **{cell(dn)}** ({vol}, {dn['folded']} vs {r['input']['folded']})"
                     f" | {cell(r['taubin_default'])} | {cell(r['hc_default'])} | {cell(r['laplacian_default'])} |"
                     f" {cell(r['twostep_default'])} | {cell(r[best_key])} {LABEL[best_key[:-5]]} | {cell(r['gf_best'])} |")
    return L + [""]


def render(paths, out_dir):
    md = ["# GeoFilter Denoise against MeshLab's smoothers\n",
          "Generated by `experiments/run compare_denoise`. Rows marked *best (oracle)* are the best of a"
          " sweep scored against the truth, which a user does not have.\n"]
    merged = {"feature": [], "noise": []}
    for p in paths:
        with open(p) as f:
            r = json.load(f)
        for k in merged:
            merged[k] += r[k]
    md += summary(merged)
    for k, title in (("feature", "Feature-scale: remove a pattern of small bumps, keep the large ones"),
                     ("noise", "Sampling noise: per-vertex Gaussian noise, nothing selected")):
        if merged[k]:
            md.append(f"## {title}\n")
        for case in merged[k]:
            md += [f"### {case['name']}\n", table(case), "", f"Floors: {case['floors']}\n"]
    with open(os.path.join(out_dir, "denoise.md"), "w") as out:
        out.write("\n".join(md))
    with open(os.path.join(out_dir, "denoise.json"), "w") as out:
        json.dump(merged, out, indent=1, default=str)


def save(out_dir, md, results, t0, final=False):
    """Written after every case, so an interrupted run keeps what it measured."""
    total = time.perf_counter() - t0
    tail = [f"Total run {total:.0f} s." + ("" if final else " (partial: the run was still going)") + "\n"]
    with open(os.path.join(out_dir, "denoise.md"), "w") as out:
        out.write("\n".join(md + tail))
    with open(os.path.join(out_dir, "denoise.json"), "w") as out:
        json.dump(results, out, indent=1, default=str)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "denoise"))
    ap.add_argument("--only", choices=["feature", "noise"])
    ap.add_argument("--meshes", default=",".join(NOISE_MESHES))
    ap.add_argument("--workdir")
    ap.add_argument("--render", nargs="+", metavar="JSON", help="only rewrite <out>/denoise.md from earlier runs' JSON")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.render:
        render(args.render, args.out)
        return
    work = args.workdir or tempfile.mkdtemp(prefix="compare-denoise-")
    t0 = time.perf_counter()
    results = {"feature": [], "noise": []}
    md = ["# GeoFilter Denoise against MeshLab's smoothers\n",
          "Everything through meshlabserver 2020.09 and the plugin of this tree. Rows marked *best (oracle)* are"
          " the best of a sweep scored against the truth, which a user does not have.\n"]

    if args.only != "noise":
        md.append("## Feature-scale: remove a pattern of small bumps, keep the large ones\n")
        for i, (name, tv, bv, f, rs, centre) in enumerate(feature_cases()):
            print(name, flush=True)
            d = os.path.join(work, f"feature{i}")
            os.makedirs(d, exist_ok=True)
            inp = os.path.join(d, "input.ply")
            c.write_and_reload(inp, bv, f)
            truth_v = c.write_and_reload(os.path.join(d, "truth.ply"), tv, f)
            truth = (truth_v, c.face_normals(truth_v, f), c.signed_volume(truth_v, f), c.is_closed(f))
            gf = [(f"n = {n}, cutoff radius {k:g} x r_small", butterworth_step(2 / (k * rs) ** 2, n, 1))
                  for n, ks in ((4, (1.0, 1.5, 2.0, 2.5, 3.0, 4.0)), (8, (2.0, 2.5, 3.0))) for k in ks]
            rows, sweeps = run_case(d, inp, f, truth, gf, [select_bump(centre, rs), denoise_step(True)])
            fl = floors_feature(rows)
            height = float(np.max(np.linalg.norm(bv - tv, axis=1)))
            detail = own_detail(d, os.path.join(d, "truth.ply"), truth_v, f, rows["denoise"], height)
            results["feature"].append({"name": name, "rows": rows, "sweeps": sweeps, "floors": fl, "own_detail": detail})
            md += [f"### {name}\n", table(results["feature"][-1]), "", f"Floors: {fl}\n",
                   f"The truth's own detail that the separating lowpass removes: median {detail:.3g} of the bumps' height.\n"
                   if detail is not None else ""]
            print("  RMS 1e-3: " + ", ".join(f"{k} {1e3 * rows[k]['rms']:.3f}" for k, _ in ROWS), flush=True)
            save(args.out, md, results, t0)

    if args.only != "feature":
        md.append("## Sampling noise: per-vertex Gaussian noise, nothing selected\n")
        # Level by level, so that a partial run covers every mesh at the middle level first.
        noise_cases = [(m, k, "normal") for k in (0.3, 0.5, 0.1) for m in args.meshes.split(",")]
        noise_cases += [(m, 0.3, "random") for m in args.meshes.split(",")]
        noise_cases += [("bunny00", k, "random") for k in (0.1, 0.5)]
        for mesh, k, direction in noise_cases:
            if mesh not in args.meshes.split(","):
                continue
            name = f"{mesh} sigma={k:g}h {direction}"
            print(name, flush=True)
            v, f = c.load_normalised(mesh)
            d = os.path.join(work, name.replace(" ", "_"))
            os.makedirs(d, exist_ok=True)
            clean = c.write_and_reload(os.path.join(d, "clean.ply"), v, f)
            rng = np.random.default_rng([SEED, NOISE_MESHES.index(mesh), int(k * 10), direction == "random"])
            noise = c.sampling_noise(clean, f, k, direction, rng)
            inp = os.path.join(d, "input.ply")
            noisy = c.write_and_reload(inp, clean + noise, f)
            hn = c.mean_edge_length(noisy, f)
            truth = (clean, c.face_normals(clean, f), c.signed_volume(clean, f), c.is_closed(f))
            gf = [(f"umbrella, n = 4, sc = {s:g}", butterworth_step(s, 4, 3)) for s in UMBRELLA_CUTOFFS]
            gf += [(f"cotangent, n = 4, cutoff radius {q:g} h", butterworth_step(2 / (q * hn) ** 2, 4, 1)) for q in COT_K]
            gf += [(f"intrinsic Delaunay, n = 4, cutoff radius {q:g} h", butterworth_step(2 / (q * hn) ** 2, 4, 2))
                   for q in (1.0, 1.5)]
            rows, sweeps = run_case(d, inp, f, truth, gf, [c.select_none(), denoise_step(False)])
            fl = floors_noise(rows)
            results["noise"].append({"name": name, "rows": rows, "sweeps": sweeps, "floors": fl})
            md += [f"### {name}\n", table(results["noise"][-1]), "", f"Floors: {fl}\n"]
            print("  RMS 1e-3: " + ", ".join(f"{k} {1e3 * rows[k]['rms']:.3f}" for k, _ in ROWS), flush=True)
            save(args.out, md, results, t0)

    save(args.out, md, results, t0, final=True)
    total = time.perf_counter() - t0
    print(f"wrote {args.out}/denoise.md, denoise.json; {total:.0f} s")
    if pages.partial_run(ap, args):
        print("a partial run: docs/results/denoise.md left as it was")
    else:
        pages.write_page("denoise", "\n".join(md[:2] + summary(results) + md[2:] + [f"Total run {total:.0f} s."]))
    if not args.workdir:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
