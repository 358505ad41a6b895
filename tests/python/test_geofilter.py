"""The Python module: same filters, names and defaults as the filter table, numpy in and out,
the core's errors as exceptions, and the same result as the command-line tool."""
import os
import subprocess
import tempfile
import threading
import time

import numpy as np
import pytest

import cli_harness as h
import filter_table
import geofilter
from shapes import fibonacci_sphere


def noisy_sphere(levels=3, radius=0.5, seed=1):
    v, f = h.icosphere(levels, radius)
    rng = np.random.default_rng(seed)
    v = v * (1 + 0.02 * rng.standard_normal((len(v), 1)))
    return np.ascontiguousarray(v), np.asarray(f, dtype=np.int32)


def test_every_filter_of_the_table_is_a_function():
    for name in [f["cli_name"] for f in filter_table.TABLE]:
        assert name in geofilter.filters
        assert callable(getattr(geofilter, name))


@pytest.mark.parametrize("preset,extra", [("lowpass", []), ("notch", []), ("exaggerate", []), ("polezero", []),
                                           ("lowpass", ["--radius", "0.2"])])
def test_results_equal_the_command_line_tool(preset, extra):
    v, f = noisy_sphere()
    with tempfile.TemporaryDirectory() as d:
        source, target = os.path.join(d, "in.off"), os.path.join(d, "out.ply")
        h.write_off(source, v, f)
        p = subprocess.run([h.tool(), preset, *extra, source, target], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        expected = h.read_ply(target).vertices
    kwargs = {"radius": float(extra[1])} if extra else {}
    out, report = getattr(geofilter, preset)(v, f, **kwargs)
    assert out.shape == v.shape and out.dtype == np.float64
    scale = np.abs(expected).max()
    assert np.abs(out - expected).max() <= 1e-12 * scale
    assert report["seconds"]["total"] > 0 and report["log"]


def test_radius_sets_s1_and_keeps_the_ratio():
    v, f = noisy_sphere()
    _, report = geofilter.lowpass(v, f, radius=0.25)
    assert report["s1"] == pytest.approx(2 / 0.25 ** 2)
    assert any("from the feature radius r = 0.25" in line for line in report["log"])
    # Left out, the radius is this filter's fraction of the diagonal: the same mesh twice as
    # large gets half the frequency squared.
    _, small = geofilter.lowpass(v, f)
    _, large = geofilter.lowpass(2 * v, f)
    diagonal = np.linalg.norm(v.max(axis=0) - v.min(axis=0))
    assert small["s1"] == pytest.approx(2 / (0.04 * diagonal) ** 2)
    assert large["s1"] == pytest.approx(small["s1"] / 4)
    with pytest.raises(ValueError, match="radius and selected_faces"):
        geofilter.lowpass(v, f, radius=0.25, selected_faces=np.arange(len(f)))


def test_selection_mask_or_indices_measure_the_feature():
    v, f = noisy_sphere(levels=3, radius=0.5, seed=2)
    mask = np.ones(len(f), dtype=bool)
    feature, _ = geofilter.measure(v, f, mask)
    assert feature["sphere_frequency"] == pytest.approx(2 / 0.5 ** 2, rel=0.05)
    same, _ = geofilter.measure(v, f, np.arange(len(f)))
    assert same["radius"] == feature["radius"]
    out, report = geofilter.lowpass(v, f, selected_faces=mask)
    assert report["s1"] == pytest.approx(feature["sphere_frequency"])


def test_design_is_the_filter_table_design():
    g = geofilter.design("exaggerate", radius=np.sqrt(2 / 25))  # s1 = 25, s2 = 2.4 s1 = 60, 1, 3, 0.9
    assert g(0.0) == pytest.approx(1)
    assert g(25.0) == pytest.approx(3)
    assert g(60.0) == pytest.approx(1)
    assert np.allclose(g(np.array([0.0, 25.0])), [1, 3])
    assert len(g.poles) == 2


def test_bad_input_raises_the_core_message_and_leaves_the_arrays_alone():
    v, f = noisy_sphere()
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        geofilter.lowpass(v[:, :2], f)
    with pytest.raises(ValueError, match=r"shape \(m, 3\)"):
        geofilter.lowpass(v, f.ravel())
    with pytest.raises(TypeError, match="integers"):
        geofilter.lowpass(v, f.astype(float))
    bad = v.copy()
    bad[3, 1] = np.nan
    before = bad.copy()
    with pytest.raises(geofilter.Error, match="vertex 3 has a NaN"):
        geofilter.lowpass(bad, f)
    assert np.array_equal(bad, before, equal_nan=True)
    wrong = f.copy()
    wrong[5, 2] = len(v) + 7
    with pytest.raises(geofilter.Error, match=f"face 5 refers to vertex {len(v) + 7}"):
        geofilter.lowpass(v, wrong)
    with pytest.raises(ValueError, match="does not exist"):
        geofilter.lowpass(v, -np.abs(f) - 1)
    with pytest.raises(geofilter.Error, match="s1 and s2 must be finite frequencies >= 0"):
        geofilter.lowpass(v, f, s1=-1)
    with pytest.raises(TypeError, match="unknown parameter 'sigma'"):
        geofilter.lowpass(v, f, sigma=2)
    with pytest.raises(geofilter.Error, match="no faces are selected"):
        geofilter.measure(v, f, np.zeros(len(f), dtype=bool))


def test_non_contiguous_and_other_dtypes_give_the_same_result():
    v, f = noisy_sphere()
    reference, _ = geofilter.notch(v, f)
    wide = np.zeros((len(v), 6))
    wide[:, ::2] = v  # a strided view
    strided, _ = geofilter.notch(wide[:, ::2], f)
    fortran, _ = geofilter.notch(np.asfortranarray(v), np.asfortranarray(f.astype(np.int64)))
    single, _ = geofilter.notch(v.astype(np.float32).astype(np.float64), f)
    assert np.array_equal(strided, reference)
    assert np.array_equal(fortran, reference)
    assert single.shape == reference.shape


def test_the_solve_releases_the_gil():
    v, f = h.icosphere(6, 1.0)  # 40,962 vertices: the solve takes a while
    v, f = np.asarray(v), np.asarray(f)
    done = threading.Event()

    def work():
        geofilter.notch(v, f)
        done.set()

    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    elapsed = time.perf_counter() - start
    # With the GIL held for the whole solve this loop could not run while it lasts.
    assert elapsed > 0.05
    assert ticks > 0.3 * elapsed / 0.002


def test_denoise_on_a_region_through_the_module_leaves_the_rest_bit_for_bit():
    # The selection is the region: the noise goes inside it, every vertex beyond the band stays.
    v, f = h.icosphere(4, 1.0)
    v, f = np.asarray(v, dtype=float), np.asarray(f, dtype=np.int32)
    rng = np.random.default_rng(3)
    noisy = np.ascontiguousarray(v * (1 + 0.02 * rng.standard_normal((len(v), 1))))
    cap = np.all(noisy[f][:, :, 2] > 0.5, axis=1)
    out, report = geofilter.denoise(noisy, f, selected_faces=cap, region=1, blendWidth=0.2)
    assert any("sampling-noise rule" in line for line in report["log"])
    off = lambda p: np.abs(np.linalg.norm(p, axis=1) - 1)
    inside = np.unique(f[cap])
    assert np.sqrt(np.mean(off(out[inside]) ** 2)) < 0.7 * np.sqrt(np.mean(off(noisy[inside]) ** 2))
    far = noisy[:, 2] < 0.2  # the cap reaches z = 0.5, the band 0.2 along the surface at most
    assert far.sum() > len(v) // 3
    np.testing.assert_array_equal(out[far], noisy[far])


def test_point_cloud_laplacian_in_numpy_and_the_filters_on_its_triangles():
    r = 0.5
    v = fibonacci_sphere(2000, r)
    cloud = geofilter.point_cloud_laplacian(v, k=30)
    rows, cols, values = cloud["K"]
    n = len(v)
    k = np.zeros((n, n))
    k[rows, cols] = values
    m = cloud["M"]
    assert len(rows) == len(set(zip(rows.tolist(), cols.tolist())))  # each entry once
    assert np.abs(k - k.T).max() <= 1e-12 * np.abs(k).max()
    assert np.abs(k.sum(axis=1)).max() <= 1e-10 * np.abs(k).max()
    assert m.sum() == pytest.approx(4 * np.pi * r * r, rel=0.01)
    for axis in range(3):
        x = v[:, axis]
        assert x @ k @ x / (x @ (m * x)) == pytest.approx(2 / r ** 2, rel=0.02)
    assert (np.einsum("ij,ij->i", cloud["normals"], v / r) > 0.99).all()

    # The coordinates are eigenfunctions at 2/r^2: a filter through the cloud's triangles scales
    # the sphere by G(2/r^2).
    triangles = cloud["triangles"]
    assert triangles.shape[1] == 3 and triangles.max() < n
    out, _ = geofilter.exaggerate(v, triangles, radius=r)
    gain = geofilter.design("exaggerate", radius=r)(2 / r ** 2)
    assert abs(gain - 1) > 0.1
    assert np.linalg.norm(out, axis=1).mean() / r == pytest.approx(gain, rel=1e-3)

    duplicated = v.copy()
    duplicated[5] = duplicated[17]
    with pytest.raises(geofilter.Error, match="1 exact duplicate"):
        geofilter.point_cloud_laplacian(duplicated)
    with pytest.raises(geofilter.Error, match="at least 31"):
        geofilter.point_cloud_laplacian(v[:20])
