"""Point clouds on the command line: XYZ, and PLY or OBJ with vertices and no faces, are
filtered through the cloud's own Laplacian and written back in their format with the
estimated normals; --select-sphere selects points; a bad cloud is refused with nothing written.
"""

import os
import re
import unittest

import numpy as np

import cli_harness as h
from shapes import fibonacci_sphere


def noisy_sphere_cloud(count=2000, radius=1.0, noise=0.01, seed=4):
    p = fibonacci_sphere(count, radius)
    rng = np.random.default_rng(seed)
    return p * (1 + noise * rng.standard_normal((count, 1)))


def write_xyz(path, p):
    np.savetxt(path, p, fmt="%.17g")


def write_ply_cloud(path, p):
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(p)}\nproperty double x\nproperty double y\n"
                "property double z\nend_header\n")
        for x in p:
            f.write("%.17g %.17g %.17g\n" % tuple(x))


def write_obj_cloud(path, p):
    with open(path, "w") as f:
        for x in p:
            f.write("v %.17g %.17g %.17g\n" % tuple(x))


def read_ply_vertices(path):
    """The vertex element of a binary little-endian PLY as a dict of columns, and the face count."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"\n", data.index(b"end_header")) + 1
    types = {"double": "<f8", "float": "<f4", "int": "<i4", "uchar": "u1"}
    columns, faces, element = [], 0, None
    for line in data[:end].decode("ascii").splitlines():
        w = line.split()
        if w[:1] == ["element"]:
            element = w[1]
            if element == "face":
                faces = int(w[2])
            else:
                count = int(w[2])
        elif w[:1] == ["property"] and element == "vertex":
            columns.append((w[2], types[w[1]]))
    vertices = np.frombuffer(data, dtype=np.dtype(columns), count=count, offset=end)
    return vertices, faces


def read_obj_cloud(path):
    v, vn = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if w[:1] == ["v"]:
                v.append([float(x) for x in w[1:4]])
            elif w[:1] == ["vn"]:
                vn.append([float(x) for x in w[1:4]])
            elif w[:1] == ["f"]:
                raise AssertionError("a cloud was written with faces")
    return np.array(v), np.array(vn)


def sphere_deviation(p):
    """RMS distance to the best sphere about the origin (its radius the mean distance)."""
    r = np.linalg.norm(p, axis=1)
    return np.sqrt(np.mean((r - r.mean()) ** 2))


class CloudTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.workdir("cloud")
        cls.cloud = noisy_sphere_cloud()

    def path(self, name):
        return os.path.join(self.dir, name)

    def test_lowpass_brings_a_noisy_sphere_cloud_closer_to_the_sphere(self):
        source, target = self.path("noisy.xyz"), self.path("lowpassed.xyz")
        write_xyz(source, self.cloud)
        p = h.run("lowpass", "--radius", 0.3, source, target)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertIn("point cloud: 2000 points, k = 30 neighbours", p.stderr)
        out = np.loadtxt(target)
        self.assertEqual(out.shape, (2000, 6))
        before, after = sphere_deviation(self.cloud), sphere_deviation(out[:, :3])
        print(f"\nXYZ lowpass --radius 0.3: deviation from the sphere {before:.5f} -> {after:.5f}")
        self.assertLess(after, 0.5 * before)
        normals = out[:, 3:]
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-9)
        self.assertGreater(np.min(np.sum(normals * out[:, :3], axis=1)), 0, "normals point outwards")

    def test_ply_obj_and_xyz_clouds_give_the_same_points(self):
        results = {}
        for ext, writer in (("xyz", write_xyz), ("ply", write_ply_cloud), ("obj", write_obj_cloud)):
            with self.subTest(format=ext):
                source, target = self.path(f"trip.{ext}"), self.path(f"trip-out.{ext}")
                writer(source, self.cloud)
                p = h.run("exaggerate", "--radius", 0.4, source, target)
                self.assertEqual(p.returncode, 0, h.describe(p))
                self.assertIn("no faces: a point cloud", p.stderr)
                if ext == "xyz":
                    out = np.loadtxt(target)
                    points, normals = out[:, :3], out[:, 3:]
                elif ext == "ply":
                    vertices, faces = read_ply_vertices(target)
                    self.assertEqual(faces, 0)
                    points = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1)
                    normals = np.stack([vertices["nx"], vertices["ny"], vertices["nz"]], axis=1).astype(float)
                else:
                    points, normals = read_obj_cloud(target)
                self.assertEqual(points.shape, self.cloud.shape)
                self.assertEqual(normals.shape, self.cloud.shape)
                self.assertGreater(np.min(np.sum(normals * points, axis=1)), 0)
                results[ext] = (points, normals)
        for ext in ("ply", "obj"):
            np.testing.assert_allclose(results[ext][0], results["xyz"][0], rtol=0, atol=1e-12)
            np.testing.assert_allclose(results[ext][1], results["xyz"][1], rtol=0, atol=1e-6)  # PLY: float

    def test_a_cloud_with_duplicate_points_is_refused_and_nothing_written(self):
        source, target = self.path("duplicates.xyz"), self.path("duplicates-out.xyz")
        write_xyz(source, np.vstack([self.cloud, self.cloud[:3]]))
        p = h.run("lowpass", "--radius", 0.3, source, target)
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("3 exact duplicate point(s)", p.stderr)
        self.assertFalse(os.path.exists(target))

    def test_bad_xyz_lines_and_formats_are_refused(self):
        source = self.path("bad.xyz")
        with open(source, "w") as f:
            f.write("0 0 0\n1 2\n")
        p = h.run("lowpass", "--radius", 0.3, source, self.path("bad-out.xyz"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("line 2 has 2 numbers", p.stderr)
        good = self.path("good.xyz")
        write_xyz(good, self.cloud)
        p = h.run("lowpass", "--radius", 0.3, good, self.path("cloud.stl"))
        self.assertEqual(p.returncode, 1, h.describe(p))
        self.assertIn("STL stores triangles only", p.stderr)
        self.assertFalse(os.path.exists(self.path("cloud.stl")))

    def test_select_sphere_selects_points_of_a_cloud(self):
        source = self.path("select.xyz")
        write_xyz(source, fibonacci_sphere(3000, 1.0))
        p = h.run("measure", "--select-sphere", "0,0,1,0.6", source)
        self.assertEqual(p.returncode, 0, h.describe(p))
        self.assertRegex(p.stdout, r"\(\d+ points\)")
        # A cap of chord 0.6 on the unit sphere: its base radius is 0.6 * sqrt(1 - 0.09) = 0.572.
        r = float(re.search(r"measure: r = ([0-9.eE+-]+):", p.stdout).group(1))
        self.assertAlmostEqual(r, 0.6 * np.sqrt(1 - 0.09), delta=0.03)
        target = self.path("select-out.xyz")
        p = h.run("lowpass", "--region", "selected", "--select-sphere", "0,0,1,0.6", "--radius", 0.2, source, target)
        self.assertEqual(p.returncode, 0, h.describe(p))
        out = np.loadtxt(target)[:, :3]
        original = fibonacci_sphere(3000, 1.0)
        far = original[:, 2] < 0
        np.testing.assert_array_equal(out[far], np.loadtxt(source)[far])


if __name__ == "__main__":
    unittest.main()
