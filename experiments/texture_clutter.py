"""How much bump-like detail the clean surface itself holds, at the size of the bumps Denoise is
asked to remove (the feature-scale cases of compare_denoise).

Denoise driven by a selected bump removes a pattern of bumps like it. That can only work where
bumps like the selected one stand out from the surface's own detail. This measures it with the
test a template detector would make: at a vertex, fit by least squares, over the vertices within
2.5 bump radii, a quadric in the tangent plane (the surface the bump stands on) plus a Gaussian
bump of the known radius centred at the vertex, and read the Gaussian's coefficient in bump
heights. Done at random vertices of the truth (no bumps: what the surface itself looks like to
the detector) and at the bumps' centres on the bumpy mesh (what a bump looks like). Where the
two distributions overlap, no rule on that coefficient tells a bump from the surface's own detail.

Cases: the five scans with the bump texture of compare_denoise (bumps 4 mean edge lengths wide),
or with finer textures (--radii, in mean edge lengths), and compare_denoise's first procedural
case (a sphere with large bumps and 150 small ones) for contrast. No MeshLab needed.
    experiments/run texture_clutter [--radii 4,2,1.5] [--samples 2000]
"""
import argparse
import time

import numpy as np

from compare_denoise import NOISE_MESHES, feature_cases, scan_texture_case
from geofilter_experiments import common as c
from geofilter_experiments import pages

WINDOW_IN_RADII = 2.5  # the Gaussian falls to exp(-6.25) there: the window holds all of a bump


class PointGrid:
    """Vertices within a distance of a point, through a uniform grid of `cell`-sized cells."""

    def __init__(self, points, cell):
        self.points, self.cell = points, cell
        keys = np.floor(points / cell).astype(np.int64)
        order = np.lexsort(keys.T)
        starts = np.nonzero(np.any(np.diff(keys[order], axis=0) != 0, axis=1))[0] + 1
        self.cells = {tuple(keys[group[0]]): group for group in np.split(order, starts)}

    def within(self, centre, radius):
        lo, hi = np.floor((centre - radius) / self.cell).astype(int), np.floor((centre + radius) / self.cell).astype(int)
        found = [self.cells[(x, y, z)] for x in range(lo[0], hi[0] + 1) for y in range(lo[1], hi[1] + 1)
                 for z in range(lo[2], hi[2] + 1) if (x, y, z) in self.cells]
        if not found:
            return np.zeros(0, int)
        found = np.concatenate(found)
        return found[np.sum((self.points[found] - centre) ** 2, axis=1) <= radius * radius]


def bump_coefficients(points, faces, at, radius, height):
    """The fitted Gaussian's height at each vertex of `at`, in units of `height`."""
    normals = c.vertex_normals(points, faces)
    window = WINDOW_IN_RADII * radius
    grid = PointGrid(points, window)
    out = []
    for i in at:
        near = grid.within(points[i], window)
        axis = normals[near].sum(axis=0)
        axis /= np.linalg.norm(axis)
        helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
        u = np.cross(axis, helper)
        u /= np.linalg.norm(u)
        w = np.cross(axis, u)
        p = points[near] - points[i]
        x, y, z = p @ u, p @ w, p @ axis
        design = np.stack([np.ones_like(x), x, y, x * x, x * y, y * y, np.exp(-(x * x + y * y) / radius ** 2)], axis=1)
        coefficients = np.linalg.lstsq(design, z, rcond=None)[0]
        out.append(coefficients[-1] / height)
    return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=2000, help="random vertices of each truth")
    ap.add_argument("--radii", default="4,2,1.5", help="bump radii of the scans' textures, in mean edge lengths (4: the comparison's)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    name, truth, bumpy, faces, radius, centre = feature_cases()[0]
    centres = np.nonzero(np.linalg.norm(bumpy - truth, axis=1) > 0.999 * 0.24 * radius)[0]
    # The procedural case lists only the selected bump's centre; its other centres are the
    # vertices raised by (almost) the full height.
    cases = [(name, truth, bumpy, faces, radius, centres, 0.24 * radius)]
    for radius_in_edges in (float(r) for r in args.radii.split(",")):
        for mesh in NOISE_MESHES:
            name, truth, bumpy, faces, radius, small = scan_texture_case(mesh, radius_in_edges)
            cases.append((f"{name} ({radius_in_edges:g} h)", truth, bumpy, faces, radius, small, 0.25 * radius))
    rng = np.random.default_rng(20261204)
    table = ["| case | truth: bump coefficient, 5/25/50/75/95 % | at the bumps: 5/25/50/75/95 % "
             "| truth vertices above the bumps' median |", "|---|---|---|---:|"]
    print("\n".join(table))
    for name, truth, bumpy, faces, radius, centres, height in cases:
        used = np.unique(faces)
        sample = rng.choice(used, size=min(args.samples, len(used)), replace=False)
        on_truth = bump_coefficients(truth, faces, sample, radius, height)
        on_bumps = bump_coefficients(bumpy, faces, centres, radius, height)
        pct = lambda values: " / ".join(f"{q:+.2f}" for q in np.percentile(values, [5, 25, 50, 75, 95]))
        above = 100 * np.mean(on_truth >= np.median(on_bumps))
        table.append(f"| {name} | {pct(on_truth)} | {pct(on_bumps)} | {above:.1f} % |")
        print(table[-1], flush=True)
    total = time.perf_counter() - t0
    print(f"\n{total:.0f} s")
    if pages.partial_run(ap, args):
        print("a partial run: docs/results/texture-clutter.md left as it was")
        return
    pages.write_page("texture-clutter", "\n".join([
        "# Can a bump be told from the surface's own detail?", "",
        "At a vertex, a quadric in the tangent plane (what a bump stands on) plus a Gaussian of the bumps' known"
        " radius, centred there, fitted by least squares over the vertices within 2.5 bump radii; cell values are"
        " the Gaussian's coefficient in bump heights, at random vertices of the truth (no bumps: what the surface"
        " itself looks like to such a detector) and at the bumps' centres on the bumpy mesh (what a bump looks"
        " like). Quantiles 5/25/50/75/95 %; last column, the share of the truth's vertices that score at least"
        " the median bump. The cases are the feature-scale cases of `experiments/run compare_denoise`.", "",
        *table, "", f"Total run {total:.0f} s."]))


if __name__ == "__main__":
    main()
