"""GeoFilter Denoise on point clouds against MeshLab's point-set smoothers, through meshlabserver.

Cases: the vertices of five scans of meshes/ (unit bounding-box diagonal) as point clouds (no
faces), with Gaussian noise of 0.3 mean edge lengths along the normals and in random
directions: ten clouds. The truth is the clean points.

Rows:
  GeoFilter Denoise      nothing selected, on the cloud layer (its own Laplacian and normals)
  MLS projection (APSS) and (RIMLS)   MeshLab's filter_mls with the cloud as both the point set
                         and the proxy, after "Compute normals for point sets" at its defaults
                         (MLS needs normals; a cloud without them is what a scan gives): at the
                         default filter scale 2, and the best of a sweep of the scale (an oracle)
  Taubin                 on the meshed cloud (the noisy points with the clean mesh's faces), at
                         its default 10 steps and the best of a sweep: a reference, since a
                         cloud has no faces to smooth

Metrics: RMS distance to the clean points (each point to its own clean position), mean distance
to the clean surface, drift (mean signed offset along the clean normals, % of the diagonal: a
volume-like bias), over the finite points, and how many points a run left NaN (MLS does where
it cannot project; an oracle's best is picked among the runs that lost none), time (wall time
of one run minus one load-and-save run: indicative).

Writes <out>/clouds.md and <out>/clouds.json, and docs/results/clouds.md on a full run. Usage:
    experiments/run compare_clouds [--out results/clouds] [--meshes bunny00,man]
"""
import argparse
import json
import os
import shutil
import tempfile
import time

import numpy as np

from geofilter_experiments import common as c
from geofilter_experiments import pages
from geofilter_experiments.common import h

P = h.Param
SEED = 20261205
MESHES = ["bunny00", "diplodocus", "fandisk_large", "refined_elephant", "man"]
NOISE = 0.3  # mean edge lengths
MLS_SCALES = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0]
MLS_DEFAULT_SCALE = 2.0
TAUBIN_STEPS = [1, 2, 3, 5, 10, 20, 30, 50, 80]
TAUBIN_DEFAULT = 10


def point_set_normals():
    # filter_meshing's defaults of 2020.09 (the viewpoint is unused without flipFlag).
    return h.Step("Compute normals for point sets", [(P("K", "RichInt", 10), 10), (P("smoothIter", "RichInt", 0), 0),
                                                      (P("flipFlag", "RichBool", False), False),
                                                      (P("viewPos", "RichPoint3f", (0, 0, 0)), (0.0, 0.0, 0.0))])


def mls(kind, scale):
    """filter_mls's projection of layer 0 onto its own MLS surface, every parameter at 2020.09's default but the scale."""
    params = [(P("ControlMesh", "RichMesh", 0), 0), (P("ProxyMesh", "RichMesh", 0), 0),
              (P("SelectionOnly", "RichBool", False), False), (P("FilterScale", "RichFloat", 2.0), scale),
              (P("ProjectionAccuracy", "RichFloat", 1e-4), 1e-4), (P("MaxProjectionIters", "RichInt", 15), 15)]
    if kind == "APSS":
        params += [(P("SphericalParameter", "RichFloat", 1.0), 1.0), (P("AccurateNormal", "RichBool", True), True)]
    else:
        params += [(P("SigmaN", "RichFloat", 0.75), 0.75), (P("MaxRefittingIters", "RichInt", 3), 3)]
    params += [(P("MaxSubdivisions", "RichInt", 0), 0), (P("ThAngleInDegree", "RichFloat", 2.0), 2.0)]
    return h.Step(f"MLS projection ({kind})", params)


def measures(points, clean, clean_normals, f):
    """Over the finite points; `lost` counts the others (MLS leaves a point it could not project as NaN)."""
    ok = np.isfinite(points).all(axis=1)
    d = points[ok] - clean[ok]
    return {"rms": float(np.sqrt(np.mean(np.sum(d ** 2, axis=1)))),
            "surf": float(c.distance_to_surface(points[ok], clean, f).mean()),
            "drift": float(100 * np.mean(np.einsum("ij,ij->i", d, clean_normals[ok]))), "lost": int((~ok).sum())}


def best(sweep):
    """The oracle's pick: the lowest RMS among the runs that lost no point (any run, if all lost some)."""
    whole = [x for x in sweep if x["lost"] == 0] or sweep
    return dict(min(whole, key=lambda x: x["rms"]), time=None)


def run_timed(d, steps, inp, out, name, base):
    r, wall = c.run(d, steps, inputs=[inp], outputs=[(out, None)], name=name)
    if r.returncode != 0 or not os.path.exists(out):
        raise RuntimeError(f"{name} failed:\n" + r.describe())
    return r, max(wall - base, 0.0)


def run_case(d, cloud_in, mesh_in, clean, normals, f):
    m = lambda path: measures(h.read_ply(path).vertices, clean, normals, f)
    rows = {"input": dict(m(cloud_in), setting="", time=None)}
    _, base = c.run(d, [c.select_none()], inputs=[cloud_in], outputs=[(os.path.join(d, "base.ply"), None)], name="base")

    out = os.path.join(d, "denoise.ply")
    r, t = run_timed(d, [c.select_none(), c.geofilter("GeoFilter: Denoise", useSelection=False)], cloud_in, out,
                     "denoise", base)
    chosen = [line for line in r.log if "cutoff sc" in line]
    rows["denoise"] = dict(m(out), setting=chosen[-1].split("cutoff sc", 1)[-1].strip() if chosen else "", time=t)

    for kind in ("APSS", "RIMLS"):
        sweep = []
        for scale in MLS_SCALES:
            out = os.path.join(d, f"{kind}{scale:g}.ply")
            _, t = run_timed(d, [point_set_normals(), mls(kind, scale)], cloud_in, out, f"{kind}{scale:g}", base)
            sweep.append(dict(m(out), setting=f"filter scale {scale:g}", time=t, scale=scale))
        rows[kind + "_default"] = next(x for x in sweep if x["scale"] == MLS_DEFAULT_SCALE)
        rows[kind + "_best"] = best(sweep)

    outs = [os.path.join(d, f"taubin{n}.ply") for n in TAUBIN_STEPS]
    steps = [c.select_none()]
    for i, n in enumerate(TAUBIN_STEPS):
        steps += [c.current_layer(0), c.duplicate_layer(), c.taubin(n)]
    c.run(d, steps, inputs=[mesh_in], outputs=[(o, i + 1) for i, o in enumerate(outs)], name="taubin-sweep")
    sweep = [dict(m(o), setting=f"{n} steps", steps=n) for n, o in zip(TAUBIN_STEPS, outs)]
    _, t = run_timed(d, [c.select_none(), c.taubin(TAUBIN_DEFAULT)], mesh_in, os.path.join(d, "taubin-t.ply"),
                     "taubin-default", base)
    rows["taubin_default"] = dict(next(x for x in sweep if x["steps"] == TAUBIN_DEFAULT), time=t)
    rows["taubin_best"] = best(sweep)
    return rows


ROWS = [("input", "noisy input"), ("denoise", "**GeoFilter Denoise, untuned**"),
        ("APSS_default", "MLS projection (APSS), default"), ("RIMLS_default", "MLS projection (RIMLS), default"),
        ("APSS_best", "MLS projection (APSS), best (oracle)"), ("RIMLS_best", "MLS projection (RIMLS), best (oracle)"),
        ("taubin_default", "Taubin on the meshed cloud, default"), ("taubin_best", "Taubin on the meshed cloud, best (oracle)")]


def table(case):
    rows = case["rows"]
    out = ["| | RMS to the clean points (1e-3) | mean distance to the surface (1e-3) | drift (% of diagonal) |"
           " points lost (NaN) | setting | time (s) |",
           "|---|---:|---:|---:|---:|---|---:|"]
    for key, label in ROWS:
        r = rows[key]
        t = "" if r.get("time") is None else f"{r['time']:.1f}"
        out.append(f"| {label} | {1e3 * r['rms']:.3f} | {1e3 * r['surf']:.3f} | {r['drift']:+.4f} | {r['lost']} |"
                   f" {r['setting']} | {t} |")
    return "\n".join(out)


def summary(results):
    n = len(results)
    if not n:
        return []
    rms = lambda case, key: case["rows"][key]["rms"]
    beats = {k: sum(rms(x, "denoise") < rms(x, k) for x in results) for k in ("APSS_default", "RIMLS_default",
                                                                           "APSS_best", "RIMLS_best", "taubin_default")}
    worse_than_input = sum(rms(x, "denoise") >= rms(x, "input") for x in results)
    surf = lambda case, key: case["rows"][key]["surf"]
    closer = {k: sum(surf(x, "denoise") < surf(x, k) for x in results) for k in ("APSS_default", "RIMLS_default",
                                                                             "APSS_best", "RIMLS_best")}
    drift = max(abs(x["rows"]["denoise"]["drift"]) for x in results)
    ratio = lambda k: [rms(x, "denoise") / rms(x, k) for x in results]
    out = ["## Summary\n",
           f"Over {n} noisy clouds, GeoFilter Denoise (untuned) has a lower RMS distance to the clean points than:\n",
           f"- MLS projection (APSS) at its defaults in {beats['APSS_default']}/{n}, at its best scale in {beats['APSS_best']}/{n};",
           f"- MLS projection (RIMLS) at its defaults in {beats['RIMLS_default']}/{n}, at its best scale in {beats['RIMLS_best']}/{n};",
           f"- Taubin at its defaults on the meshed cloud in {beats['taubin_default']}/{n}.\n",
           f"Denoise / APSS default RMS: median {np.median(ratio('APSS_default')):.2f}, worst {max(ratio('APSS_default')):.2f};"
           f" Denoise / RIMLS default: median {np.median(ratio('RIMLS_default')):.2f}, worst {max(ratio('RIMLS_default')):.2f}.",
           f"Denoise ends farther from the truth than its input in {worse_than_input}/{n}; its largest drift is"
           f" {drift:.4f} % of the diagonal.\n",
           f"Its mean distance to the clean surface is lower than APSS's at its defaults in {closer['APSS_default']}/{n}"
           f" (at its best scale in {closer['APSS_best']}/{n}) and RIMLS's in {closer['RIMLS_default']}/{n}"
           f" ({closer['RIMLS_best']}/{n}). On a cloud, noise along the surface cannot be told from the sampling (a"
           " point moved along the surface is another sample of it): no cloud smoother removes it, and the RMS to each"
           " point's own clean position keeps it, which is why the rows with noise in random directions stay near"
           " the input's RMS.\n",
           "| cloud | input | **Denoise** | APSS default | RIMLS default | APSS best | RIMLS best | Taubin default (mesh) |",
           "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for x in results:
        r = x["rows"]
        out.append(f"| {x['name']} | " + " | ".join(f"{1e3 * r[k]['rms']:.3f}" for k in (
            "input", "denoise", "APSS_default", "RIMLS_default", "APSS_best", "RIMLS_best", "taubin_default")) + " |")
    out.append("\n(RMS distance to the clean points, 1e-3 of the diagonal.)\n")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "clouds"))
    ap.add_argument("--meshes", default=",".join(MESHES))
    ap.add_argument("--workdir")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    work = args.workdir or tempfile.mkdtemp(prefix="compare-clouds-")
    t0 = time.perf_counter()
    results = []
    md = ["# GeoFilter Denoise on point clouds against MeshLab's point-set smoothers\n",
          "Everything through meshlabserver 2020.09 and the plugin of this tree. Rows marked *best (oracle)* are"
          " the best of a sweep scored against the truth, which a user does not have.\n"]
    details = []
    for direction in ("normal", "random"):
        for mesh in args.meshes.split(","):
            name = f"{mesh} sigma={NOISE:g}h {direction}"
            print(name, flush=True)
            v, f = c.load_normalised(mesh)
            d = os.path.join(work, name.replace(" ", "_"))
            os.makedirs(d, exist_ok=True)
            clean = c.write_and_reload(os.path.join(d, "clean.ply"), v, f)
            normals = c.vertex_normals(clean, f)
            rng = np.random.default_rng([SEED, MESHES.index(mesh), direction == "random"])
            noise = c.sampling_noise(clean, f, NOISE, direction, rng)
            cloud_in, mesh_in = os.path.join(d, "cloud.ply"), os.path.join(d, "mesh.ply")
            c.write_and_reload(cloud_in, clean + noise, np.zeros((0, 3), dtype=int))
            c.write_and_reload(mesh_in, clean + noise, f)
            rows = run_case(d, cloud_in, mesh_in, clean, normals, f)
            results.append({"name": name, "points": len(v), "rows": rows})
            details += [f"### {name} ({len(v):,} points)\n", table(results[-1]), ""]
            print("  RMS 1e-3: " + ", ".join(f"{k} {1e3 * rows[k]['rms']:.3f}" for k, _ in ROWS), flush=True)
            with open(os.path.join(args.out, "clouds.json"), "w") as out:
                json.dump(results, out, indent=1)
    total = time.perf_counter() - t0
    page = md + summary(results) + ["## Every cloud\n"] + details + [f"Total run {total:.0f} s."]
    with open(os.path.join(args.out, "clouds.md"), "w") as out:
        out.write("\n".join(page) + "\n")
    print(f"wrote {args.out}/clouds.md, clouds.json; {total:.0f} s")
    if pages.partial_run(ap, args):
        print("a partial run: docs/results/clouds.md left as it was")
    else:
        pages.write_page("clouds", "\n".join(page))
    if not args.workdir:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
