"""Shared by the experiments (compare_taubin, compare_denoise, reproduce_fig6, reproduce_figures).

meshlabserver scripts are built with the integration-test harness
(tests/integration/geofilter_harness.py), which lists every GeoFilter parameter; this module
adds the MeshLab built-in filters the experiments need, a few mesh measures (normals, volume,
edge length) and the G(s) plot.
"""
import os
import re
import time

import numpy as np

import geofilter_harness as h  # tests/integration, on the path through experiments/run

from .render_meshes import read_off  # noqa: F401  (re-exported for the experiments)

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(os.path.dirname(HERE))

P = h.Param
MESHES_DIR = os.path.join(TOP, "meshes")


# ---------------------------------------------------------------------------------------------
# MeshLab 2020.09 built-in filters, with every parameter (names from the filter_unsharp,
# filter_select and filter_layer sources of 2020.09).

def select_none():
    # Taubin and HC Laplacian smooth only the selected faces whenever some are selected,
    # whatever their "Selected" flag says: clear the selection so they smooth everything.
    return h.Step("Select None", [(P("allFaces", "RichBool", True), True), (P("allVerts", "RichBool", True), True)])


def taubin(steps, lam=0.5, mu=-0.53):
    """Taubin's lambda|mu smoothing with uniform (umbrella) weights; one step = a lambda and a mu pass."""
    return h.Step("Taubin Smooth", [(P("lambda", "RichFloat", 0.5), lam), (P("mu", "RichFloat", -0.53), mu),
                                    (P("stepSmoothNum", "RichInt", 10), steps),
                                    (P("Selected", "RichBool", False), False)])


def laplacian(steps, cotangent=True):
    """VCG's Laplacian: each step moves a vertex to (p + sum w_j p_j) / (1 + sum w_j)."""
    return h.Step("Laplacian Smooth", [(P("stepSmoothNum", "RichInt", 3), steps),
                                       (P("Boundary", "RichBool", True), True),
                                       (P("cotangentWeight", "RichBool", True), cotangent),
                                       (P("Selected", "RichBool", False), False)])


def hc_laplacian():
    """One iteration of Vollmer et al.'s HC smoothing (the filter has no parameter: repeat it)."""
    return h.Step("HC Laplacian Smooth", [])


def duplicate_layer():
    """Copies the current layer into a new layer, which becomes the current one."""
    return h.Step("Duplicate Current layer", [])


def current_layer(position):
    """Makes layer `position` (order of creation, as -l counts) the current one."""
    return h.Step("Change the current layer", [(P("layer", "RichMesh", 0), position)])


# ---------------------------------------------------------------------------------------------
# GeoFilter steps that match the installed plugin

_declared = None


def _declared_types():
    """Parameter types per filter, in the dialog's order, from `meshlabserver -d` of the
    installed prefix (the dump gives types and labels, not names)."""
    global _declared
    if _declared is None:
        import tempfile
        with tempfile.TemporaryDirectory(prefix="geofilter-dump-") as d:
            text = h.dump_filters(d)
        _declared = {}
        for m in re.finditer(r"\\section f\d+ (.*?) \n(.*?)(?=\\section|\Z)", text, re.S):
            _declared[m.group(1).strip()] = re.findall(r"<TR><TD> \\c (\w+) +</TD>", m.group(2))
    return _declared


def geofilter(name, **values):
    """The harness's GeoFilter step, after checking that the installed plugin declares the
    parameters the harness (which follows the source tree) writes: a plugin in build/ built
    from an older tree would make meshlabserver 2020.09 abort on the script."""
    declared = _declared_types().get(name)
    if declared is None:
        raise SystemExit(f"the installed plugin has no filter '{name}': rebuild it (scripts/build.sh)")
    expected = [p.rich_type[len("Rich"):] for p in h.FILTERS[name]]
    if declared != expected:
        raise SystemExit(f"the installed plugin's '{name}' declares {declared}, this tree {expected}: rebuild it"
                         " (scripts/build.sh)")
    return h.geofilter(name, **values)


def run(workdir, steps, inputs=(), outputs=(), name="script", timeout=600):
    """Runs meshlabserver; returns (Run, wall seconds). Fails loudly on a non-zero exit."""
    t = time.perf_counter()
    r = h.run_meshlabserver(workdir, steps, inputs=inputs, outputs=outputs, timeout=timeout,
                            script_name=name + ".mlx")
    wall = time.perf_counter() - t
    if r.returncode != 0:
        raise SystemExit(f"meshlabserver failed ({name}):\n" + r.describe())
    return r, wall


def geofilter_times(r):
    """The GeoFilter solver's own timings ("...; time 1.12 s (assembly ...") in log order."""
    return [float(m.group(1)) for line in r.log for m in [re.search(r"; time ([0-9.eE+-]+) s", line)] if m]


# ---------------------------------------------------------------------------------------------
# Mesh measures

def face_normals(v, f, unit=True):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    if unit:
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    return n


def vertex_normals(v, f):
    """Area-weighted vertex normals (sum of the unnormalised face normals)."""
    fn = face_normals(v, f, unit=False)
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, f[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def signed_volume(v, f):
    """Divergence theorem; the volume enclosed only when the mesh is closed and oriented."""
    t = v[f]
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)


def edges(f):
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def is_closed(f):
    _, counts = edges(f)
    return bool(np.all(counts == 2))


def mean_edge_length(v, f):
    e, _ = edges(f)
    return float(np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1).mean())


def sampling_noise(clean, f, edges_sigma, direction, rng):
    """Gaussian per-vertex noise of `edges_sigma` mean edge lengths of the clean mesh: along its
    vertex normals ("normal"), or in random directions ("random", the same sigma overall, a
    third of the variance on each axis)."""
    sigma = edges_sigma * mean_edge_length(clean, f)
    if direction == "normal":
        return (sigma * rng.standard_normal(len(clean)))[:, None] * vertex_normals(clean, f)
    return sigma * rng.standard_normal((len(clean), 3)) / np.sqrt(3)


def bbox_diagonal(v):
    return float(np.linalg.norm(v.max(0) - v.min(0)))


# ---------------------------------------------------------------------------------------------
# The designed response

def plot_gains(ax, designs, s_range, marks=()):
    """log-log |G(s)| of eq. 15 for each (label, dict(s1, s2, G0, G1, Ginf)), s1 and s2 marked.

    Where G < 0 a curve turns dashed (a log axis cannot show the sign, and a flipped band is what
    a user must not miss); each curve's maximum |G| is dotted. marks: extra (s, label) lines,
    e.g. the mesh's sampling limit."""
    colors = ["tab:blue", "tab:red", "tab:green", "tab:purple"]
    s = np.geomspace(*s_range, 3000)
    for (label, p), col in zip(designs, colors):
        g = h.eq15_gain(s, p["s1"], p["s2"], p["G0"], p["G1"], p["Ginf"])
        a = np.abs(g)
        ax.loglog(s, np.where(g >= 0, a, np.nan), "-", color=col, lw=1.6, label=label)
        if np.any(g < 0):
            ax.loglog(s, np.where(g < 0, a, np.nan), "--", color=col, lw=1.6, label=label + ": G < 0 (flipped)")
        k = int(np.argmax(a))
        ax.plot(s[k], a[k], "o", color=col, ms=4)
        for x, name in ((p["s1"], "s1"), (p["s2"], "s2")):
            ax.axvline(x, color=col, lw=0.7, ls=":")
            ax.text(x, 0.98, name, color=col, fontsize=7, rotation=90, va="top", ha="right",
                    transform=ax.get_xaxis_transform())
    for x, name in marks:
        if s_range[0] < x < s_range[1]:  # a label outside the axes would land on the neighbour panel
            ax.axvline(x, color="0.4", lw=1.0, ls="-.")
            ax.text(x, 0.5, name, color="0.3", fontsize=7, rotation=90, va="center", ha="right",
                    transform=ax.get_xaxis_transform())
    ax.axhline(1.0, color="0.6", lw=0.8)
    ax.set_xlim(*s_range)
    lo, hi = ax.get_ylim()
    ax.set_ylim(min(lo, 0.1), max(hi, 3.0))  # at least a decade and a half, so the ticks read
    ax.set_xlabel("s (1/length², mesh units)")
    ax.set_ylabel("|G(s)|")
    ax.grid(True, which="both", alpha=0.25)
    # Below the axes: inside, it would hide curves or the s1/s2 labels whatever the corner.
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)


def _segment_distance(p, a, b):
    ab = b - a
    t = np.clip(np.einsum("...j,...j->...", p - a, ab) / np.maximum(np.einsum("...j,...j->...", ab, ab), 1e-300), 0, 1)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1)


def distance_to_surface(points, v, f, k=16):
    """Distance from each point to the triangle mesh (v, f): exact point-triangle distances to the
    k triangles whose centroids are nearest. Exact whenever the closest triangle is among them,
    which holds for points within about an edge length of a reasonably shaped mesh."""
    from scipy.spatial import cKDTree
    tri = v[f]
    _, cand = cKDTree(tri.mean(axis=1)).query(points, k=k)
    a, b, cc = tri[cand, 0], tri[cand, 1], tri[cand, 2]  # (n, k, 3)
    p = points[:, None, :]
    n = np.cross(b - a, cc - a)
    n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-300)
    dist_plane = np.einsum("...j,...j->...", p - a, n)
    q = p - dist_plane[..., None] * n  # projection on the triangle's plane
    # Inside when q is on the inner side of all three edges.
    inside = np.ones(q.shape[:2], dtype=bool)
    for u, w in ((a, b), (b, cc), (cc, a)):
        inside &= np.einsum("...j,...j->...", np.cross(w - u, q - u), n) >= 0
    edge = np.minimum(np.minimum(_segment_distance(p, a, b), _segment_distance(p, b, cc)), _segment_distance(p, cc, a))
    return np.where(inside, np.abs(dist_plane), edge).min(axis=1)


def load_normalised(name):
    """A mesh of meshes/ centred and scaled to unit bounding-box diagonal."""
    v, f = read_off(os.path.join(MESHES_DIR, name + ".off"))
    lo, hi = v.min(0), v.max(0)
    return (v - (lo + hi) / 2) / np.linalg.norm(hi - lo), f


def write_and_reload(path, v, f):
    """Writes the PLY meshlabserver will read and returns what it will see (float32 coordinates)."""
    h.write_ply_ascii(path, h.PlyMesh(v, f))
    return h.read_ply(path).vertices
