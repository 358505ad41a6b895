"""GeoFilter from Python on a real mesh: the Stanford bunny (meshes/bunny00.off, extracted by
scripts/setup.sh), smoothed below a feature radius of 3 % of its size, then the ears (every
face above 85 % of the height) measured and exaggerated at their own frequency. Run from the repository with the module on the path:

    PYTHONPATH=build/python /usr/bin/python3 python/example_bunny.py
"""
import os
import sys

import numpy as np

import geofilter


def read_off(path):
    with open(path) as f:
        tokens = f.read().split()
    n, m = int(tokens[1]), int(tokens[2])
    v = np.array(tokens[4:4 + 3 * n], float).reshape(n, 3)
    f = np.array(tokens[4 + 3 * n:4 + 3 * n + 4 * m], np.int32).reshape(m, 4)[:, 1:]
    return v, f


here = os.path.dirname(os.path.abspath(__file__))
V, F = read_off(os.path.join(here, "..", "meshes", "bunny00.off"))
size = np.linalg.norm(V.max(0) - V.min(0))

smooth, report = geofilter.lowpass(V, F, radius=0.03 * size)
print(f"lowpass: s1 = {report['s1']:.4g}, {report['iterations']} CG iterations, {report['seconds']['total']:.2f} s")
print(f"  moved the vertices by {np.linalg.norm(smooth - V, axis=1).mean() / size:.2e} of the size on average")

# The ears: every face whose vertices lie above 85 % of the bunny's height.
top = V[:, 1].min() + 0.85 * (V[:, 1].max() - V[:, 1].min())
ears = (V[F][:, :, 1] > top).all(axis=1)
feature, _ = geofilter.measure(V, F, ears)
print(f"ears: {feature['face_count']} faces, radius {feature['radius']:.4g}, s = {feature['cylinder_frequency']:.4g}")
grown, report = geofilter.exaggerate(V, F, selected_faces=ears, featureShape=1)
print(f"exaggerate: s1 = {report['s1']:.4g}; G(s1) = {geofilter.design('exaggerate', s1=report['s1'], s2=report['s1'] * 60 / 25)(report['s1']):.3g}")
sys.exit(0 if np.isfinite(grown).all() and not np.array_equal(grown, V) else 1)
