"""Procedural meshes for the Python tests and experiments (the Python side of shapes.h)."""

import numpy as np


def icosphere(levels, radius=1.0, center=(0.0, 0.0, 0.0)):
    """Icosahedron, each triangle split in four `levels` times, projected on the sphere."""
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [np.array(v, float) / np.linalg.norm(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return np.array(verts) * radius + np.asarray(center, float), np.array(faces, dtype=np.int64)


def bumpy_sphere(levels=5, count=60, rho=0.15, seed=5):
    """A unit icosphere covered with `count` Gaussian bumps 0.24 rho * exp(-(d/rho)^2) high, their
    centres at least 2 rho apart (random, fixed seed). Returns (bare, bumpy, faces, centres)."""
    bare, faces = icosphere(levels)
    rng = np.random.default_rng(seed)
    centres = []
    while len(centres) < count:
        c = rng.normal(size=3)
        c /= np.linalg.norm(c)
        if all(np.linalg.norm(c - o) >= 2 * rho for o in centres):
            centres.append(c)
    height = sum(0.24 * rho * np.exp(-np.sum((bare - c) ** 2, axis=1) / rho ** 2) for c in centres)
    return bare, bare * (1 + height)[:, None], faces, centres


def fibonacci_sphere(count, radius=1.0):
    """`count` points spread evenly over a sphere of `radius` (the Fibonacci spiral): a cloud."""
    i = np.arange(count)
    z = 1 - (2 * i + 1) / count
    ring = np.sqrt(1 - z * z)
    angle = np.pi * (3 - np.sqrt(5)) * i
    return radius * np.column_stack([ring * np.cos(angle), ring * np.sin(angle), z])
