"""The module's filters on point clouds: V alone (F omitted, None or empty) is a cloud filtered
through its own Laplacian, its selection selected_vertices, its estimated normals in the report."""
import os

import numpy as np
import pytest

import cli_harness as h
import geofilter
from shapes import fibonacci_sphere


def bumpy_icosphere(levels, slide=0.25):
    """Gentle bumps on an icosphere whose vertices slid along the sphere by `slide` edge lengths
    (RMS): its triangles are then no longer the Delaunay ones the cloud's operator builds, so the
    two operators differ and the comparison means something."""
    v, f = h.icosphere(levels, 1.0)
    edge = 1.1 / 2 ** levels
    v = v + slide * edge * np.random.default_rng(11).standard_normal(v.shape)
    u = v / np.linalg.norm(v, axis=1, keepdims=True)
    bumps = 0.05 * np.sin(3 * u[:, 0]) * np.sin(2 * u[:, 1] + 1) * np.cos(2 * u[:, 2])
    return np.ascontiguousarray(u * (1 + bumps)[:, None]), np.asarray(f, dtype=np.int32)


def test_lowpass_of_a_meshs_vertices_as_a_cloud_matches_the_meshs():
    v, f = bumpy_icosphere(5, 0.25)
    by_mesh, _ = geofilter.lowpass(v, f, radius=0.3)
    by_cloud, report = geofilter.lowpass(v, radius=0.3)
    moved = np.sqrt(np.mean(np.sum((by_mesh - v) ** 2, axis=1)))
    apart = np.sqrt(np.mean(np.sum((by_cloud - by_mesh) ** 2, axis=1)))
    print(f"\nbumpy icosphere ({len(v)} vertices): lowpass moved it {moved:.3g} RMS, cloud - mesh {apart:.3g} RMS "
          f"({100 * apart / moved:.2f} %)")
    assert moved > 1e-3
    assert apart > 1e-6 * moved  # different operators
    assert apart < 0.05 * moved
    assert report["log"][0].startswith(f"point cloud: {len(v)} points, k = 30 neighbours (fans among the nearest 15), ")
    normals = report["normals"]
    assert normals.shape == v.shape
    assert np.min(np.sum(normals * v, axis=1)) > 0
    # None and an empty (0, 3) array say the same.
    for no_faces in (None, np.zeros((0, 3), dtype=np.int32), np.zeros((0, 3))):
        again, _ = geofilter.lowpass(v, no_faces, radius=0.3)
        np.testing.assert_array_equal(again, by_cloud)


def test_a_smooth_scans_vertices_as_a_cloud_are_lowpassed_like_the_scan():
    """The refined elephant (44k vertices, a smooth scan of meshes/): its vertices alone, lowpassed
    at two feature sizes, move as the mesh's cotangent operator moves them, to 5 % of the motion."""
    path = os.path.join(os.path.dirname(__file__), "..", "..", "meshes", "refined_elephant.off")
    mesh = h.read_off(path)
    v = np.asarray(mesh.vertices, dtype=np.float64)
    v = (v - (v.min(0) + v.max(0)) / 2) / np.linalg.norm(v.max(0) - v.min(0))
    f = np.asarray(mesh.faces, dtype=np.int32)
    for radius in (0.02, 0.05):
        by_mesh, _ = geofilter.lowpass(v, f, radius=radius)
        by_cloud, _ = geofilter.lowpass(v, radius=radius)
        moved = np.sqrt(np.mean(np.sum((by_mesh - v) ** 2, axis=1)))
        apart = np.sqrt(np.mean(np.sum((by_cloud - by_mesh) ** 2, axis=1)))
        print(f"\nrefined elephant, radius {radius}: lowpass moved it {moved:.3g} RMS, cloud - mesh {apart:.3g} RMS "
              f"({100 * apart / moved:.2f} %)")
        assert moved > 1e-3
        assert apart < 0.05 * moved


def test_denoise_with_nothing_selected_brings_a_noisy_sphere_cloud_closer():
    clean = fibonacci_sphere(3000)
    rng = np.random.default_rng(7)
    noisy = clean * (1 + 0.01 * rng.standard_normal((len(clean), 1)))
    out, report = geofilter.denoise(noisy)
    before = np.sqrt(np.mean((np.linalg.norm(noisy, axis=1) - 1) ** 2))
    after = np.sqrt(np.mean((np.linalg.norm(out, axis=1) - 1) ** 2))
    print(f"\nDenoise on a noisy sphere cloud (3000 points, 1 % radial noise): RMS distance to the sphere "
          f"{before:.5f} -> {after:.5f}")
    assert after < 0.6 * before
    assert any("sampling-noise rule" in line for line in report["log"])


def test_selected_vertices_give_the_feature():
    v = fibonacci_sphere(3000)
    cap = np.flatnonzero(v[:, 2] > 0.8)
    feature, report = geofilter.measure(v, selected_vertices=cap)
    assert feature["point_count"] == len(cap) and feature["face_count"] == 0
    assert feature["radius"] == pytest.approx(0.6, rel=0.03)  # the cap's base radius, sqrt(1 - 0.8^2)
    _, lowpassed = geofilter.lowpass(v, selected_vertices=v[:, 2] > 0.8)
    assert lowpassed["s1"] == pytest.approx(feature["sphere_frequency"])
    with pytest.raises(ValueError, match="selected_vertices selects a point cloud"):
        mesh_v, mesh_f = bumpy_icosphere(2)
        geofilter.lowpass(mesh_v, mesh_f, selected_vertices=[0, 1, 2])


def test_bad_clouds_are_refused():
    v = fibonacci_sphere(500)
    with pytest.raises(geofilter.Error, match="duplicate"):
        geofilter.lowpass(np.vstack([v, v[:1]]), radius=0.3)
    with pytest.raises(geofilter.Error, match="has 10 points"):
        geofilter.lowpass(v[:10], radius=0.3)
    with pytest.raises(geofilter.Error, match="yet 1 faces"):
        geofilter.lowpass(v, None, selected_faces=[0])


def test_denoise_on_a_cloud_keeps_only_the_motion_across_the_surface():
    """A cloud's fans are no faces to fold: with noise along the normals Denoise keeps, at every
    point, only the lowpass's motion along the normal, never its drift along the surface (which
    on irregular sampling is pure error against each point's own clean position)."""
    rng = np.random.default_rng(5)
    u = rng.standard_normal((4000, 3))
    clean = u / np.linalg.norm(u, axis=1, keepdims=True)  # uniform, irregular sampling
    noisy = clean * (1 + 0.01 * rng.standard_normal((len(clean), 1)))
    out, report = geofilter.denoise(noisy)
    radial = noisy / np.linalg.norm(noisy, axis=1, keepdims=True)
    motion = out - noisy
    across = np.sum(motion * radial, axis=1)
    sideways = np.linalg.norm(motion - across[:, None] * radial, axis=1)
    print(f"\nDenoise on a 4000-point random sphere cloud: motion across RMS {np.sqrt(np.mean(across ** 2)):.3g}, "
          f"sideways RMS {np.sqrt(np.mean(sideways ** 2)):.3g}")
    line = next(line for line in report["log"] if line.startswith("motion along the normals only"))
    assert " 0 kept the lowpass's position" in line, line
    # The fans' normals are the surface's up to the sampling: a sideways part of a few percent.
    assert np.sqrt(np.mean(sideways ** 2)) < 0.1 * np.sqrt(np.mean(across ** 2))
