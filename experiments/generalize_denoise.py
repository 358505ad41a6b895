"""Denoise on case families it was not tuned on, against MeshLab's smoothers.

Every case is drawn from a family by a seed. Even seeds are the *tuning* half: Denoise's
constants may be chosen on them only. Odd seeds are the *report* half: what docs/ states.
A family varies what a user's mesh varies; a case fixes one draw of it.

Feature scale (one bump of a pattern selected, the truth is the surface without the pattern):
  sphere-gauss     sphere with large bumps, a pattern of Gaussian bumps
  sphere-mixed     sphere with large bumps, raised-cosine bumps and dents of both signs
  torus-dents      torus with large bumps, spherical-cap dents
  scan-plateau     a smoothed scan, plateau bumps and dents of both signs
  patch-grooves    an open wavy patch (with a boundary), ridges and grooves
  noisy-bumps      a case of one of the five above, with sampling noise on top (0.1-0.4 mean edge
                   lengths, along the normals or in random directions): a scan of a patterned surface
  In each: radii spread +-30 % about the pattern's, coverage 5-40 % (overlaps allowed), heights
  0.15-0.3 radii; the user selects one element of the pattern the way Conditional Face
  Selection does, centred up to a quarter radius off, 1-1.6 radii wide.
Sampling noise (nothing selected, the truth is the clean mesh):
  scan-normal      a scan, noise along the normals, 0.1-0.5 mean edge lengths
  scan-random      a scan, noise in random directions, 0.1-0.5
  scan-depth       a scan, noise along one view direction growing with depth (a scanner's)
  scan-patchy      a scan, noise loud in a few patches and fading to none between them, either way
  scan-outliers    a scan, noise 0.1-0.2 along the normals and 0.5-2 % of vertices thrown 3-6 edges
  anisotropic      tori sampled 3-5x longer one way than the other, jittered (no face folded); noise either way
  holes-debris     a scan with holes, a second closed component and small debris fragments
  cad              sharp-edged parts (a box, a capped cylinder, fandisk); noise either way
  scan-faint       a scan with faint noise, 0-0.05 mean edge lengths, either way: nearly clean,
                   where what Denoise must not do is make it worse

Denoise runs through meshlabserver 2020.09 and the plugin of this tree, as the smoothers do
(with --denoise-only, through the Python module and without MeshLab: the tuning loop; with
--as-clouds, the sampling-noise cases' vertices alone, as point clouds, the same way).
MeshLab's Taubin, HC Laplacian, Laplacian (cotangent) and TwoStep run at their defaults and at
their best over a sweep scored against the truth (an oracle no user has).

    experiments/run generalize_denoise [--half tuning|report | --seeds 6,7,...] [--denoise-only | --as-clouds] [--families a,b]

--seeds draws cases from seeds that neither half holds (from 6 up): held out from every choice
made so far. Writes <out>/generalize-<half or seeds>.json (and .md); the report half of a full run
writes docs/results/generalize.md.
"""
import argparse
import json
import os
import shutil
import tempfile
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import spsolve

from geofilter_experiments import common as c
from geofilter_experiments import pages
from geofilter_experiments.common import h
from shapes import icosphere  # tests/support
import compare_denoise as cd

SEEDS = range(6)
HALF = {"tuning": [s for s in SEEDS if s % 2 == 0], "report": [s for s in SEEDS if s % 2 == 1]}
SCANS = ["bunny00", "diplodocus", "fandisk_large", "refined_elephant", "man"]
ORGANIC = ["bunny00", "diplodocus", "refined_elephant", "man"]


# ---------------------------------------------------------------------------------------------
# Surfaces

def torus(rings, segments, big, small):
    return cd.torus(rings, segments, big, small)


def torus_normals(v, big):
    core = v.copy()
    core[:, 2] = 0
    core[:, :2] *= (big / np.linalg.norm(core[:, :2], axis=1))[:, None]
    n = v - core
    return n / np.linalg.norm(n, axis=1)[:, None]


def grid_patch(count, radius):
    """A disc of radius `radius` in the plane, triangulated on a square grid (count x count)."""
    x = np.linspace(-radius, radius, count)
    xx, yy = np.meshgrid(x, x, indexing="ij")
    keep = (xx ** 2 + yy ** 2 <= radius ** 2).ravel()
    index = -np.ones(count * count, dtype=np.int64)
    index[keep] = np.arange(keep.sum())
    faces = []
    for i in range(count - 1):
        for j in range(count - 1):
            a, b, cc, d = i * count + j, i * count + j + 1, (i + 1) * count + j, (i + 1) * count + j + 1
            for t in ((a, cc, b), (b, cc, d)):
                if all(keep[k] for k in t):
                    faces.append([index[k] for k in t])
    v = np.stack([xx.ravel()[keep], yy.ravel()[keep], np.zeros(keep.sum())], 1)
    return v, np.array(faces)


def box(m):
    """A unit cube, each face an m x m grid of square cells split in two: sharp edges."""
    verts, faces, at = [], [], {}

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in at:
            at[key] = len(verts)
            verts.append(p)
        return at[key]

    t = np.linspace(-0.5, 0.5, m + 1)
    for axis in range(3):
        for side in (-0.5, 0.5):
            u, w = [k for k in range(3) if k != axis]
            for i in range(m):
                for j in range(m):
                    q = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[w] = side, t[i + di], t[j + dj]
                        q.append(vid(p))
                    a, b, cc, d = q
                    tri = [(a, b, cc), (a, cc, d)]
                    # Outward orientation: (b - a) x (c - a) along +axis when side > 0.
                    e = np.cross(verts[b] - verts[a], verts[cc] - verts[a])
                    if np.sign(e[axis]) != np.sign(side):
                        tri = [(a, cc, b), (a, d, cc)]
                    faces += tri
    return np.array(verts), np.array(faces)


def capped_cylinder(segments, rings, radius, height):
    """A closed cylinder, its faces turned outwards: its side a grid, each cap a fan of rings around a centre vertex."""
    a = 2 * np.pi * np.arange(segments) / segments
    zs = np.linspace(-height / 2, height / 2, rings + 1)
    v = [np.array([radius * np.cos(x), radius * np.sin(x), z]) for z in zs for x in a]
    f = []
    for i in range(rings):
        for j in range(segments):
            p, q = i * segments + j, i * segments + (j + 1) % segments
            f += [(p, q, p + segments), (q, q + segments, p + segments)]
    caps = max(2, int(round(radius / (height / rings))))
    for z, top in ((-height / 2, False), (height / 2, True)):
        edge_ring = list(range(rings * segments, (rings + 1) * segments)) if top else list(range(segments))
        prev = edge_ring
        for k in range(1, caps):
            rr = radius * (1 - k / caps)
            ring = list(range(len(v), len(v) + segments))
            v += [np.array([rr * np.cos(x), rr * np.sin(x), z]) for x in a]
            for j in range(segments):
                p0, p1, q0, q1 = prev[j], prev[(j + 1) % segments], ring[j], ring[(j + 1) % segments]
                f += [(p0, p1, q0), (p1, q1, q0)] if top else [(p0, q0, p1), (p1, q0, q1)]
            prev = ring
        centre = len(v)
        v.append(np.array([0, 0, z]))
        for j in range(segments):
            f.append((prev[j], prev[(j + 1) % segments], centre) if top else (prev[j], centre, prev[(j + 1) % segments]))
    return np.array(v), np.array(f)


def uniform_laplacian(n, f):
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    a = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
    a = ((a + a.T) > 0).astype(float)
    return sp.diags(np.asarray(a.sum(1)).ravel()) - a


def smoothed(v, f, amount):
    """Implicit uniform-Laplacian smoothing, (I + amount L)^-1 v twice: a smooth base surface."""
    system = (sp.identity(len(v)) + amount * uniform_laplacian(len(v), f)).tocsc()
    for _ in range(2):
        v = np.column_stack([spsolve(system, v[:, k]) for k in range(3)])
    return v


def normalised(v):
    lo, hi = v.min(0), v.max(0)
    return (v - (lo + hi) / 2) / np.linalg.norm(hi - lo)


# ---------------------------------------------------------------------------------------------
# Patterns

PROFILES = {
    "gaussian": lambda t: np.exp(-t ** 2),
    "raised cosine": lambda t: np.where(t < 2, 0.5 * (1 + np.cos(np.pi * np.minimum(t, 2) / 2)), 0.0),
    "spherical cap": lambda t: np.sqrt(np.maximum(0.0, 1 - (t / 1.5) ** 2)),
    "plateau": lambda t: np.where(t < 0.7, 1.0, np.where(t < 1.6, 0.5 * (1 + np.cos(np.pi * (np.minimum(t, 1.6) - 0.7) / 0.9)), 0.0)),
}
SUPPORT = {"gaussian": 3.0, "raised cosine": 2.0, "spherical cap": 1.5, "plateau": 1.6}


def pattern(v, n, area, rng, radius, profile, signs, coverage, elongation=1.0):
    """Adds bumps (sign +1) and dents (-1) along the normals n: centres random vertices at
    least 1.2 radii apart (tails overlap), radii radius x U[0.7, 1.3], heights 0.15-0.3 of
    their radius, until their footprints (pi (1.5 r)^2 each) reach `coverage` of the area.
    `elongation` > 1 stretches each along a random tangent (ridges, grooves).
    Returns (bumpy v, [(centre index, radius, sign)])."""
    out = v.copy()
    placed, covered = [], 0.0
    for i in rng.permutation(len(v)):
        if covered >= coverage * area:
            break
        r = radius * rng.uniform(0.7, 1.3)
        if any(np.linalg.norm(v[i] - v[j]) < 1.2 * max(r, rj) for j, rj, _ in placed):
            continue
        sign = rng.choice(signs)
        height = rng.uniform(0.15, 0.3) * r
        d = v - v[i]
        if elongation > 1:
            t = np.cross(n[i], rng.standard_normal(3))
            t /= np.linalg.norm(t)
            along = d @ t
            d = d - (1 - 1 / elongation) * along[:, None] * t  # distances shrink along t
        dist = np.linalg.norm(d, axis=1) / r
        near = dist < SUPPORT[profile]
        out[near] += (sign * height * PROFILES[profile](dist[near]))[:, None] * n[near]
        placed.append((int(i), r, int(sign)))
        covered += np.pi * (1.5 * r) ** 2 * elongation
    return out, placed


def large_bumps(v, n, rng, count, radius, height):
    out = v.copy()
    for i in rng.choice(len(v), count, replace=False):
        d2 = np.sum((v - v[i]) ** 2, axis=1)
        out += (height * np.exp(-d2 / radius ** 2))[:, None] * n
    return out


def surface_area(v, f):
    return float(0.5 * np.linalg.norm(c.face_normals(v, f, unit=False), axis=1).sum())


def user_selection(bumpy, f, centre_index, radius, normal, rng):
    """A user's selection of one pattern element: the faces within 1-1.6 radii of a point up to
    a quarter radius off its centre (Conditional Face Selection's sphere)."""
    t = np.cross(normal, rng.standard_normal(3))
    t /= np.linalg.norm(t)
    centre = bumpy[centre_index] + rng.uniform(0, 0.25) * radius * t
    reach = rng.uniform(1.0, 1.6) * radius
    inside = np.linalg.norm(bumpy - centre, axis=1) < reach
    return centre, reach, np.flatnonzero(inside[f].all(axis=1))


def feature_case(family, seed):
    if family == "noisy-bumps":
        return noisy_feature_case(seed)
    rng = np.random.default_rng([20261205, sum(map(ord, family)), seed])
    coverage = rng.uniform(0.05, 0.40)
    if family in ("sphere-gauss", "sphere-mixed"):
        v, f = icosphere(6)
        truth = large_bumps(v, v.copy(), rng, 6, 0.4, 0.12)
        radius = rng.uniform(0.05, 0.09)
        profile, signs = ("gaussian", [1]) if family == "sphere-gauss" else ("raised cosine", [1, -1])
        elongation = 1.0
    elif family == "torus-dents":
        v, f = torus(240, 96, 1.0, 0.4)
        truth = large_bumps(v, torus_normals(v, 1.0), rng, 5, 0.3, 0.08)
        radius, profile, signs, elongation = rng.uniform(0.035, 0.06), "spherical cap", [-1], 1.0
    elif family == "scan-plateau":
        v, f = c.load_normalised(ORGANIC[seed % len(ORGANIC)])
        truth = normalised(smoothed(v, f, 3.0))
        hb = c.mean_edge_length(truth, f)
        radius, profile, signs, elongation = rng.uniform(4, 6) * hb, "plateau", [1, -1], 1.0
    elif family == "patch-grooves":
        v, f = grid_patch(181, 0.5)
        k = rng.uniform(4, 8, size=2)
        v[:, 2] = 0.06 * np.sin(k[0] * v[:, 0] + rng.uniform(0, 6)) * np.cos(k[1] * v[:, 1] + rng.uniform(0, 6))
        truth = v
        hb = c.mean_edge_length(truth, f)
        radius, profile, signs, elongation = rng.uniform(3, 5) * hb, "gaussian", [1, -1], 3.0
    else:
        raise ValueError(family)
    normal = c.vertex_normals(truth, f)
    bumpy, placed = pattern(truth, normal, surface_area(truth, f), rng, radius, profile, signs, coverage, elongation)
    chosen, r, sign = placed[rng.integers(len(placed))]
    centre, reach, faces = user_selection(bumpy, f, chosen, r, normal[chosen], rng)
    name = (f"{family} #{seed}: {len(placed)} {profile} {'bumps' if signs == [1] else 'dents' if signs == [-1] else 'bumps and dents'}"
            f" r={radius:.3g}, coverage {100 * coverage:.0f} %, a {'bump' if sign > 0 else 'dent'} selected")
    return dict(name=name, family=family, seed=seed, truth=truth, input=bumpy, f=f, selection=(centre, reach, faces))


def noisy_feature_case(seed):
    """A case of another feature family (by seed) with sampling noise on top: a scan of a
    patterned surface. The truth is still the surface without the pattern, and without noise."""
    bases = [family for family in FEATURE if family != "noisy-bumps"]
    base = bases[seed % len(bases)]
    case = feature_case(base, seed)
    rng = np.random.default_rng([20261205, sum(map(ord, "noisy-bumps")), seed])
    v, f = case["input"], case["f"]
    level, direction = rng.uniform(0.1, 0.4), ["normal", "random"][rng.integers(2)]
    step = level * c.mean_edge_length(v, f)
    noise = rng.standard_normal(v.shape) if direction == "random" else rng.standard_normal(len(v))[:, None] * c.vertex_normals(v, f)
    case["input"] = v + step * noise
    case["name"] = (case["name"].replace(base, "noisy-bumps", 1) +
                    f", sigma {level:.2f}h {'along the normals' if direction == 'normal' else 'in random directions'}")
    case["family"] = "noisy-bumps"
    return case


def with_holes_and_debris(v, f, rng):
    """Cuts 2-4 holes (3-6 edges wide), adds a closed sphere beside the scan and 4-10 small
    debris fragments (a few faces each, lifted off the surface)."""
    hb = c.mean_edge_length(v, f)
    centroid = v[f].mean(axis=1)
    keep = np.ones(len(f), bool)
    for i in rng.choice(len(f), rng.integers(2, 5), replace=False):
        keep &= np.linalg.norm(centroid - centroid[i], axis=1) > rng.uniform(3, 6) * hb
    f = f[keep]
    parts_v, parts_f = [v], [f]
    offset = len(v)
    sv, sf = icosphere(3, radius=0.06, center=v.max(0) + 0.08)
    parts_v.append(sv)
    parts_f.append(sf + offset)
    offset += len(sv)
    normal = c.vertex_normals(v, f)
    for i in rng.choice(len(f), rng.integers(4, 11), replace=False):
        near = np.flatnonzero(np.linalg.norm(centroid[keep] - centroid[keep][i], axis=1) < rng.uniform(1, 2.5) * hb)
        if len(near) == 0:
            continue
        ff = f[near]
        used, local = np.unique(ff, return_inverse=True)
        parts_v.append(v[used] + rng.uniform(3, 8) * hb * normal[f[near[0], 0]])
        parts_f.append(local.reshape(-1, 3) + offset)
        offset += len(used)
    v, f = np.vstack(parts_v), np.vstack(parts_f)
    used = np.zeros(len(v), bool)
    used[f.ravel()] = True
    remap = -np.ones(len(v), dtype=np.int64)
    remap[used] = np.arange(used.sum())
    return v[used], remap[f]


def noise_case(family, seed):
    rng = np.random.default_rng([20261205, sum(map(ord, family)), seed])
    direction = ["normal", "random"][rng.integers(2)]
    if family == "anisotropic":
        stretch = rng.uniform(3, 5)
        v, f = torus(int(300), int(300 / stretch / 2.5), 1.0, 0.4)
        n = torus_normals(v, 1.0)
        # Slid along the surface by at most a quarter of the vertex's shortest edge: two corners
        # of a face then close in on each other by at most half its shortest edge, less than any
        # of its heights (a face 5x longer than wide is 0.98 of its short side high), so the
        # truth folds no face. Slid by a quarter of the mean edge length, 18-22 % of its faces
        # faced inwards, and every smoother counted them as folds it had made.
        e, _ = c.edges(f)
        length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
        shortest = np.full(len(v), np.inf)
        np.minimum.at(shortest, e[:, 0], length)
        np.minimum.at(shortest, e[:, 1], length)
        jitter = rng.standard_normal(v.shape)
        jitter -= np.einsum("ij,ij->i", jitter, n)[:, None] * n
        v = v + (0.25 * shortest / np.maximum(1.0, np.linalg.norm(jitter, axis=1)))[:, None] * jitter
        v = normalised(v)
        detail = f"stretched {stretch:.1f}x"
    elif family == "cad":
        shape = ["box", "cylinder", "fandisk_large"][seed % 3]
        if shape == "box":
            v, f = box(40)
        elif shape == "cylinder":
            v, f = capped_cylinder(120, 60, 0.3, 0.9)
        else:
            v, f = c.load_normalised(shape)
        v = normalised(v)
        detail = shape
    else:
        scan = SCANS[(seed + sum(map(ord, family))) % len(SCANS)]
        v, f = c.load_normalised(scan)
        detail = scan
        if family == "holes-debris":
            v, f = with_holes_and_debris(v, f, rng)
            v = normalised(v)
    hb = c.mean_edge_length(v, f)
    if family in ("scan-normal", "scan-random"):
        direction = family[5:]
    k = rng.uniform(0.1, 0.5) if family != "scan-faint" else rng.uniform(0.0, 0.05)
    if family == "scan-depth":
        view = rng.standard_normal(3)
        view /= np.linalg.norm(view)
        depth = v @ view
        t = (depth - depth.min()) / (depth.max() - depth.min())
        sigma = k * hb * (0.3 + 1.4 * t)
        noise = (sigma * rng.standard_normal(len(v)))[:, None] * view
        label = f"{detail}, sigma {k:.2f}h on average along a view direction, growing with depth"
    elif family == "scan-patchy":
        # Noise in patches: loud about a few places, fading to none between them (a scan merged
        # from takes of different quality, a region rescanned). Its strength is a sum of 1-3
        # Gaussian blobs 0.1-0.3 of the diagonal wide about random vertices, scaled to mean k.
        blobs = np.zeros(len(v))
        diagonal = np.linalg.norm(v.max(0) - v.min(0))
        for _ in range(rng.integers(1, 4)):
            centre = v[rng.integers(len(v))]
            width = rng.uniform(0.1, 0.3) * diagonal
            blobs += np.exp(-np.sum((v - centre) ** 2, axis=1) / (2 * width ** 2))
        sigma = k * hb * blobs / blobs.mean()
        noise = sigma[:, None] * c.sampling_noise(v, f, 1.0 / hb, direction, rng)
        label = f"{detail}, sigma {k:.2f}h on average {'along the normals' if direction == 'normal' else 'in random directions'}," \
                f" in patches (0-{sigma.max() / hb:.2f}h)"
    elif family == "scan-outliers":
        k = rng.uniform(0.1, 0.2)
        noise = c.sampling_noise(v, f, k, "normal", rng)
        share = rng.uniform(0.005, 0.02)
        thrown = rng.random(len(v)) < share
        noise[thrown] += (rng.choice([-1, 1], thrown.sum()) * rng.uniform(3, 6, thrown.sum()) * hb)[:, None] * \
            c.vertex_normals(v, f)[thrown]
        label = f"{detail}, sigma {k:.2f}h along the normals, {100 * share:.1f} % outliers"
    else:
        noise = c.sampling_noise(v, f, k, direction, rng)
        label = f"{detail}, sigma {k:.2f}h {'along the normals' if direction == 'normal' else 'in random directions'}"
    return dict(name=f"{family} #{seed}: {label}", family=family, seed=seed, truth=v, input=v + noise, f=f, selection=None)


FEATURE = ["sphere-gauss", "sphere-mixed", "torus-dents", "scan-plateau", "patch-grooves", "noisy-bumps"]
NOISE = ["scan-normal", "scan-random", "scan-depth", "scan-patchy", "scan-outliers", "anisotropic", "holes-debris", "cad",
         "scan-faint"]


def make_case(family, seed):
    return feature_case(family, seed) if family in FEATURE else noise_case(family, seed)


# ---------------------------------------------------------------------------------------------
# Measures

def closed_components(f, n):
    """Faces of each closed component (a component whose every edge has two faces, 20 faces or more)."""
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    graph = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    out = {}
    for comp in np.unique(label[f[:, 0]]):
        ff = f[label[f[:, 0]] == comp]
        if len(ff) >= 20 and c.is_closed(ff):
            out[int(comp)] = ff
    return out


def closed_volumes(v, components):
    """Signed volume of each closed component (closed_components)."""
    return {comp: c.signed_volume(v, ff) for comp, ff in components.items()}


def noise_volume_spread(case, components, volumes):
    """Per closed component of the truth (volumes: their closed_volumes): one standard deviation, in %
    of its volume, of the volume change that noise like the case's makes (to first order, the sum
    over vertices of the volume's gradient dotted with the noise; its variance estimated from the
    noise drawn). A uniform offset of the surface is indistinguishable from this part of the noise."""
    v = case["truth"]
    e = case["input"] - v
    out = {}
    for comp, ff in components.items():
        volume = volumes[comp]
        grad = np.zeros_like(v)
        a, b, d = ff[:, 0], ff[:, 1], ff[:, 2]
        np.add.at(grad, a, np.cross(v[b], v[d]) / 6)
        np.add.at(grad, b, np.cross(v[d], v[a]) / 6)
        np.add.at(grad, d, np.cross(v[a], v[b]) / 6)
        out[comp] = float(100 * np.sqrt(np.sum(np.einsum("ij,ij->i", grad, e) ** 2)) / abs(volume)) if volume else None
    return out


def pleats(v, f):
    """The faces that turn against the faces around them: a face whose normal points away from the
    sum of the area-weighted normals of the faces sharing a vertex with it (one term per vertex
    shared, itself left out). A scan can hold a few such pleats; a smoother that unfolds one is
    counted as folding it, since the truth's own face points the other way."""
    area_normal = c.face_normals(v, f, unit=False)
    at_vertex = np.zeros_like(v)
    for k in range(3):
        np.add.at(at_vertex, f[:, k], area_normal)
    around = at_vertex[f].sum(axis=1) - 3 * area_normal
    return np.einsum("ij,ij->i", area_normal, around) < 0


def measure(v, case, truth_normals, truth_volumes, components, truth_pleats):
    f = case["f"]
    d = np.linalg.norm(v - case["truth"], axis=1)
    fn = c.face_normals(v, f)
    ang = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", fn, truth_normals), -1, 1)))
    vols = closed_volumes(v, components)
    dvol = [100 * (vols[k] - t) / abs(t) for k, t in truth_volumes.items() if k in vols and t != 0]
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "nerr": float(ang.mean()), "folded": int(np.sum(ang > 90)),
            "folded_pleats": int(np.sum((ang > 90) & truth_pleats)), "dvol": float(max(dvol, key=abs)) if dvol else None}


# ---------------------------------------------------------------------------------------------
# Runs

def denoise_python(case, cloud=False):
    """Denoise through the Python module: on the mesh, or on its vertices alone as a point cloud."""
    import geofilter
    if cloud:
        out, report = geofilter.denoise(case["input"])
        return out, report["log"]
    kwargs = {}
    if case["selection"] is not None:
        kwargs["selected_faces"] = case["selection"][2].astype(np.int32)
    out, report = geofilter.denoise(case["input"], case["f"].astype(np.int32), **kwargs)
    return out, report["log"]


def denoise_log_lines(log):
    """The lines of Denoise's log that say which path ran and what it chose."""
    keys = ("pattern of bumps", "cutoff sc", "noise model", "no lowpass scored below", "fell back",
            "then fitted to its face normals", "the pattern did not explain")
    return [line for line in log if any(k in line for k in keys)]


def run_meshlab(d, case, inp):
    """Denoise and MeshLab's smoothers through meshlabserver: {row: (v, setting)}."""
    out = {}
    sel = case["selection"]
    steps = [cd.select_bump(sel[0], sel[1]), cd.denoise_step(True)] if sel is not None else [c.select_none(), cd.denoise_step(False)]
    path = os.path.join(d, "denoise.ply")
    r, _ = c.run(d, steps, inputs=[inp], outputs=[(path, None)], name="denoise")
    out["denoise"] = (h.read_ply(path).vertices, denoise_log_lines(r.log))
    for key, counts in cd.SWEEP.items():
        if key == "twostep":
            counts = [1, 3, 10]
            outs = [os.path.join(d, f"{key}{n}.ply") for n in counts]
            for n, o in zip(counts, outs):
                c.run(d, [c.select_none()] + cd.STEP_FOR[key](n), inputs=[inp], outputs=[(o, None)], name=f"{key}{n}")
        else:
            outs = [os.path.join(d, f"{key}{n}.ply") for n in counts]
            c.run(d, cd.chain(key, counts), inputs=[inp], outputs=[(o, i) for i, o in enumerate(outs)], name=key + "-sweep")
        for n, o in zip(counts, outs):
            out[f"{key}:{n}"] = (h.read_ply(o).vertices, f"{n} steps")
    return out


def judge(case, rows):
    """The issue's floors for one case, from its rows of measures."""
    dn, inp = rows["denoise"], rows["input"]
    default = {k: rows[f"{k}:{cd.DEFAULT[k]}"] for k in cd.SWEEP}
    best = {k: min((r for key, r in rows.items() if key.startswith(k + ":")), key=lambda r: r["rms"]) for k in cd.SWEEP}
    vol_ok = dn["dvol"] is None or abs(dn["dvol"]) <= 0.3
    if case["family"] in FEATURE:
        return {"beats defaults": all(dn["rms"] < r["rms"] and dn["nerr"] < r["nerr"] for r in default.values()),
                "beats best": all(dn["rms"] < r["rms"] for r in best.values()),
                "not worse than input": dn["rms"] <= inp["rms"], "volume": vol_ok}
    t = default["taubin"]
    return {"below Taubin, HC, Laplacian": all(dn["rms"] < default[k]["rms"] for k in ("taubin", "hc", "laplacian")),
            "within 10 % of Taubin": dn["rms"] <= 1.1 * t["rms"], "normals vs Taubin": dn["nerr"] <= t["nerr"],
            "volume": vol_ok, "folds": dn["folded"] <= inp["folded"], "not worse than input": dn["rms"] <= inp["rms"]}


def run_case(case, work, denoise_only, cloud=False):
    f = case["f"]
    d = os.path.join(work, f"{case['family']}-{case['seed']}")
    os.makedirs(d, exist_ok=True)
    inp = os.path.join(d, "input.ply")
    noisy = c.write_and_reload(inp, case["input"], f)
    case["truth"] = c.write_and_reload(os.path.join(d, "truth.ply"), case["truth"], f)
    case["input"] = noisy
    tn = c.face_normals(case["truth"], f)
    closed = closed_components(f, len(case["truth"]))
    tvol = closed_volumes(case["truth"], closed)
    truth_pleats = pleats(case["truth"], f)
    m = lambda v: measure(v, case, tn, tvol, closed, truth_pleats)
    rows = {"input": m(noisy)}
    t = time.perf_counter()
    if denoise_only:
        v, log = denoise_python(case, cloud)
        rows["denoise"] = dict(m(v), log=denoise_log_lines(log))
    else:
        for key, (v, setting) in run_meshlab(d, case, inp).items():
            rows[key] = dict(m(v), log=setting) if key == "denoise" else dict(m(v), setting=setting)
    rows["denoise"]["seconds"] = time.perf_counter() - t
    result = {"name": case["name"], "family": case["family"], "seed": case["seed"], "vertices": len(noisy), "rows": rows,
              "volume_noise": noise_volume_spread(case, closed, tvol)}
    if not denoise_only:
        result["floors"] = judge(case, rows)
    return result


# ---------------------------------------------------------------------------------------------
# The page

def fmt(r):
    return f"{1e3 * r['rms']:.3f} / {r['nerr']:.1f}°"


def page(results, half, seeds):
    L = [f"Cases of the **{half}** half (seeds {', '.join(map(str, seeds))} of each family); Denoise's constants"
         " were chosen on the other half." if half == "report" else
         f"Cases of the {half} half." if half in HALF else
         f"Cases of seeds {', '.join(map(str, seeds))}, which neither half holds.",
         "RMS vertex distance to the truth in 1e-3 of the bounding-box diagonal / mean face-normal error. *best* is a"
         " smoother's best over its sweep, scored against the truth (an oracle no user has).\n"]
    for kind, families in (("Feature scale", FEATURE), ("Sampling noise", NOISE)):
        rs = [r for r in results if r["family"] in families]
        if not rs:
            continue
        L += [f"## {kind}: floors met\n", "| floor | cases met |", "|---|---:|"]
        for key in rs[0]["floors"]:
            L.append(f"| {key} | {sum(r['floors'][key] for r in rs)}/{len(rs)} |")
        missed_volume = [r for r in rs if not r["floors"]["volume"]]
        if kind == "Sampling noise" and missed_volume:
            L += ["", "Where the volume floor is missed: Denoise's volume error, its input's, and one standard deviation"
                  " of what noise like the case's does to the volume (first order, from the noise drawn). Noise moves a"
                  " closed surface's volume by its mean offset along the normals, which no smoother can tell from the"
                  " surface's own.\n"]
            for r in missed_volume:
                spread = max((x for x in r["volume_noise"].values() if x is not None), default=None)
                L.append(f"- {r['name']}: {r['rows']['denoise']['dvol']:+.2f} %, input {r['rows']['input']['dvol']:+.2f} %"
                         + (f", noise ±{spread:.2f} %" if spread is not None else ""))
        missed_folds = [r for r in rs if not r["floors"].get("folds", True)]
        if missed_folds:
            L += ["", "Where the folds floor is missed: faces turned more than 90° from the truth's, for Denoise, its input"
                  " and default Taubin, and how many of each are pleats of the truth (faces the truth itself turns against"
                  " the faces around them: a smoother that unfolds one is counted as folding it).\n"]
            for r in missed_folds:
                w = r["rows"]
                L.append("- " + r["name"] + ": " + ", ".join(
                    f"{label} {w[key]['folded']} ({w[key].get('folded_pleats', 0)} pleats)"
                    for label, key in (("Denoise", "denoise"), ("input", "input"), ("Taubin", f"taubin:{cd.DEFAULT['taubin']}"))))
        L += ["", f"## {kind}: per family (median and worst of Denoise's RMS relative to the input, and to default Taubin)\n",
              "| family | cases | Denoise / input, median | worst | Denoise / Taubin default, median | worst | floors missed |",
              "|---|---:|---:|---:|---:|---:|---|"]
        for fam in families:
            fr = [r for r in rs if r["family"] == fam]
            if not fr:
                continue
            a = np.array([r["rows"]["denoise"]["rms"] / r["rows"]["input"]["rms"] for r in fr])
            b = np.array([r["rows"]["denoise"]["rms"] / r["rows"][f"taubin:{cd.DEFAULT['taubin']}"]["rms"] for r in fr])
            missed = sorted({k for r in fr for k, ok in r["floors"].items() if not ok})
            L.append(f"| {fam} | {len(fr)} | {np.median(a):.3f} | {a.max():.3f} | {np.median(b):.3f} | {b.max():.3f} |"
                     f" {', '.join(missed) or '–'} |")
        L += ["", f"## {kind}: every case\n",
              "| case | input | **Denoise** (volume, folded vs input) | Taubin | HC | Laplacian | TwoStep | best smoother (oracle) |",
              "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for r in rs:
            w = r["rows"]
            dn = w["denoise"]
            best = min((v for k, v in w.items() if ":" in k), key=lambda v: v["rms"])
            best_key = next(k for k, v in w.items() if v is best)
            vol = "–" if dn["dvol"] is None else f"{dn['dvol']:+.2f} %"
            L.append(f"| {r['name']} ({r['vertices']} vertices) | {fmt(w['input'])} | **{fmt(dn)}** ({vol}, {dn['folded']} vs"
                     f" {w['input']['folded']}) | " + " | ".join(fmt(w[f"{k}:{cd.DEFAULT[k]}"]) for k in cd.SWEEP) +
                     f" | {fmt(best)} {cd.LABEL[best_key.split(':')[0]]} {best_key.split(':')[1]} |")
        L.append("")
        L += ["What Denoise did, per case (its log):\n"]
        L += [f"- {r['name']}: {'; '.join(r['rows']['denoise']['log'])}" for r in rs]
        L.append("")
    return "\n".join(L)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--half", choices=list(HALF), default="report")
    ap.add_argument("--seeds", default="", help="comma-separated seeds from 6 up instead of a half: draws held out from every choice")
    ap.add_argument("--families", default=",".join(FEATURE + NOISE),
                    help="comma-separated families, or 'feature' / 'noise' for all of one kind")
    ap.add_argument("--denoise-only", action="store_true", help="Denoise through the Python module only, no MeshLab")
    ap.add_argument("--as-clouds", action="store_true",
                    help="the sampling-noise cases' vertices as point clouds (no faces), Denoise only")
    ap.add_argument("--out", default=os.path.join(c.TOP, "results", "generalize"))
    args = ap.parse_args()
    if args.as_clouds:
        if any(fam not in NOISE + ["noise"] for fam in args.families.split(",")):
            ap.error("--as-clouds takes sampling-noise families only: " + ",".join(NOISE))
        args.denoise_only = True
    seeds = HALF[args.half]
    label = args.half
    if args.seeds:
        seeds = [int(s) for s in args.seeds.split(",")]
        if any(s in SEEDS for s in seeds):
            ap.error(f"--seeds takes seeds that neither half holds ({len(SEEDS)} and up)")
        label = "seeds-" + "-".join(map(str, seeds))
    if args.families != ap.get_default("families"):
        label += "-" + args.families.replace(",", "-")  # a run of other families writes files of its own
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="generalize-")
    t0 = time.perf_counter()
    results = []
    families = [f for name in args.families.split(",") for f in {"feature": FEATURE, "noise": NOISE}.get(name, [name])]
    for fam in families:
        for seed in seeds:
            case = make_case(fam, seed)
            r = run_case(case, work, args.denoise_only, args.as_clouds)
            results.append(r)
            w = r["rows"]
            extra = "" if args.denoise_only else "  " + " ".join(f"{k} {ok}" for k, ok in r["floors"].items() if not ok)
            print(f"{r['name']}: input {fmt(w['input'])} -> Denoise {fmt(w['denoise'])}"
                  f" ({w['denoise']['rms'] / w['input']['rms']:.3f} of the input's RMS; {w['denoise']['seconds']:.1f} s){extra}",
                  flush=True)
            name = f"generalize-{label}{'-clouds' if args.as_clouds else ''}.json"
            with open(os.path.join(args.out, name), "w") as out:
                json.dump(results, out, indent=1)
    total = time.perf_counter() - t0
    print(f"{len(results)} cases, {total:.0f} s")
    shutil.rmtree(work)
    if args.denoise_only:
        return
    text = page(results, label, seeds) + f"\nTotal run {total:.0f} s."
    with open(os.path.join(args.out, f"generalize-{label}.md"), "w") as out:
        out.write(text)
    if args.half == "report" and not pages.partial_run(ap, args):
        pages.write_page("generalize", "# Denoise on cases it was not tuned on\n\n" + text)


if __name__ == "__main__":
    main()
