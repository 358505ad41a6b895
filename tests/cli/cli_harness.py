"""Runs the `geofilter` command-line tool and reads/writes the meshes it exchanges.

Everything a test needs is written here from the file formats' and the paper's
definitions, independently of the C++ code under test.
"""

import os
import re
import shutil
import struct
import subprocess
import tempfile

import numpy as np
from reference_design import eq15_gain  # noqa: F401 (used as harness.eq15_gain)
from shapes import icosphere  # noqa: F401 (tests/support; used as harness.icosphere)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_TOOL = os.path.join(HERE, "..", "..", "build", "filter_geofilter", "cli", "geofilter")


def tool():
    """The tool to test: $GEOFILTER_CLI (set by ctest) or the default build's. Fails, never skips."""
    path = os.path.abspath(os.environ.get("GEOFILTER_CLI", DEFAULT_TOOL))
    if not os.access(path, os.X_OK):
        raise AssertionError(f"no geofilter tool at {path}: build it with cmake --build build --target geofilter")
    return path


def run(*args, timeout=60, stdin=subprocess.DEVNULL, **kwargs):
    return subprocess.run([tool(), *map(str, args)], capture_output=True, text=True, errors="replace",
                          timeout=timeout, stdin=stdin, **kwargs)


def describe(p):
    return f"command: {' '.join(p.args)}\nexit: {p.returncode}\n--- stdout ---\n{p.stdout}\n--- stderr ---\n{p.stderr}"


def log_lines(p):
    return [l[len("geofilter: "):] for l in p.stderr.splitlines() if l.startswith("geofilter: ")]


def log_value(p, pattern):
    """The first number captured by `pattern` in the log (stderr)."""
    m = re.search(pattern, p.stderr)
    if not m:
        raise AssertionError(f"no match for {pattern!r} in the log\n" + describe(p))
    return float(m.group(1))


def workdir(test_id):
    """A fresh folder per test: under $GEOFILTER_TEST_WORKDIR (kept for inspection) or /tmp."""
    base = os.environ.get("GEOFILTER_TEST_WORKDIR")
    if not base:
        return tempfile.mkdtemp(prefix="geofilter-cli-")
    d = os.path.join(base, re.sub(r"[^A-Za-z0-9_.-]", "_", test_id))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


# ---------------------------------------------------------------------------------------------
# Writers (what a user's other programs would produce)

def write_off(path, v, f):
    with open(path, "w") as out:
        out.write(f"OFF\n{len(v)} {len(f)} 0\n")
        out.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in v)
        out.writelines("3 %d %d %d\n" % tuple(t) for t in f)


def write_obj(path, v, f):
    with open(path, "w") as out:
        out.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in v)
        out.writelines("f %d %d %d\n" % tuple(t + 1) for t in f)


def write_ply(path, v, f, face_flags=None):
    """ASCII PLY; `face_flags` (ints) adds the per-face 'flags' property MeshLab writes
    when asked to save face flags (selection = bit 0x20)."""
    with open(path, "w") as out:
        out.write("ply\nformat ascii 1.0\n")
        out.write(f"element vertex {len(v)}\nproperty double x\nproperty double y\nproperty double z\n")
        out.write(f"element face {len(f)}\nproperty list uchar int vertex_indices\n")
        if face_flags is not None:
            out.write("property int flags\n")
        out.write("end_header\n")
        out.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in v)
        for i, t in enumerate(f):
            out.write("3 %d %d %d" % tuple(t) + (f" {int(face_flags[i])}" if face_flags is not None else "") + "\n")


def write_stl(path, v, f):
    """Binary STL: every triangle with its own three corners, as the format has it."""
    with open(path, "wb") as out:
        out.write(b"geofilter test".ljust(80, b" "))
        out.write(struct.pack("<I", len(f)))
        for t in f:
            a, b, c = v[t[0]], v[t[1]], v[t[2]]
            n = np.cross(b - a, c - a)
            n = n / np.linalg.norm(n)
            out.write(struct.pack("<12fH", *n, *a, *b, *c, 0))


WRITERS = {"off": write_off, "obj": write_obj, "ply": write_ply, "stl": write_stl}


# ---------------------------------------------------------------------------------------------
# Readers

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


class MeshData:
    def __init__(self, vertices, faces, face_flags=None):
        self.vertices = np.asarray(vertices, float).reshape(-1, 3)
        self.faces = np.asarray(faces, np.int64).reshape(-1, 3)
        self.face_flags = face_flags


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    fmt, elements = None, []
    for line in data[:end].decode("ascii").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            elements[-1][2].append((w[4], w[3], w[2]) if w[1] == "list" else (w[2], w[1], None))
    body = data[end:]
    out = {}
    if fmt == "ascii":
        tokens, pos = body.split(), 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for pname, _, ltype in props:
                    if ltype:
                        k = int(tokens[pos]); pos += 1
                        row[pname] = [int(x) for x in tokens[pos:pos + k]]; pos += k
                    else:
                        row[pname] = float(tokens[pos]); pos += 1
                rows.append(row)
            out[name] = rows
        v = [[r["x"], r["y"], r["z"]] for r in out["vertex"]]
        fr = out.get("face", [])
        faces = [r["vertex_indices"] for r in fr]
        flags = np.array([int(r["flags"]) for r in fr]) if fr and "flags" in fr[0] else None
        return MeshData(v, faces, flags)
    if fmt != "binary_little_endian":
        raise ValueError(f"{path}: PLY format {fmt} not handled by the test reader")
    pos = 0
    arrays = {}
    for name, count, props in elements:
        dt = []
        for pname, ptype, ltype in props:
            if ltype:  # the tool writes triangles only: a list of 3 reads as a fixed field
                dt += [(pname + "_n", "<" + _PLY_TYPES[ltype]), (pname, "<" + _PLY_TYPES[ptype], (3,))]
            else:
                dt.append((pname, "<" + _PLY_TYPES[ptype]))
        arr = np.frombuffer(body, dtype=np.dtype(dt), count=count, offset=pos)
        pos += arr.nbytes
        arrays[name] = arr
    vx = arrays["vertex"]
    fa = arrays.get("face")
    if fa is not None and len(fa) and not np.all(fa["vertex_indices_n"] == 3):
        raise ValueError(f"{path}: non-triangular faces")
    flags = fa["flags"].astype(np.int64) if fa is not None and "flags" in fa.dtype.names else None
    return MeshData(np.stack([vx["x"], vx["y"], vx["z"]], axis=1), fa["vertex_indices"] if fa is not None else [], flags)


def read_off(path):
    """Vertices and faces of an OFF; anything after a face's indices (its colour) is ignored."""
    with open(path) as f:
        lines = [l.split("#")[0].split() for l in f]
    lines = [l for l in lines if l]
    if not lines[0][0].endswith("OFF"):
        raise ValueError(f"{path}: not an OFF file")
    counts = lines[0][1:] if len(lines[0]) > 1 else lines.pop(1)
    nv, nf = int(counts[0]), int(counts[1])
    v = np.array([l[:3] for l in lines[1:1 + nv]], float)
    faces = [[int(x) for x in l[1:1 + int(l[0])]] for l in lines[1 + nv:1 + nv + nf]]
    return MeshData(v, faces)


def read_obj(path):
    v, faces = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                v.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in w[1:4]])
    return MeshData(v, faces)


def read_stl(path):
    """Triangle corners as stored (3 per face, nothing shared)."""
    with open(path, "rb") as f:
        data = f.read()
    n = struct.unpack_from("<I", data, 80)[0]
    if len(data) == 84 + 50 * n:
        rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n, offset=84)
        v = rec["v"].reshape(-1, 3).astype(float)
    else:
        v = np.array(re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data), float)
    return MeshData(v, np.arange(len(v)).reshape(-1, 3))


def read_mesh(path):
    return {"ply": read_ply, "off": read_off, "obj": read_obj, "stl": read_stl}[path.rsplit(".", 1)[1].lower()](path)


def radii(vertices, center=None):
    c = vertices.mean(axis=0) if center is None else np.asarray(center)
    return np.linalg.norm(vertices - c, axis=1)


# ---------------------------------------------------------------------------------------------
# Eq. 15 comes from the shared test reference, tests/support/reference_design.py (on
# PYTHONPATH through ctest): its five conditions solved as a linear system, never a copy of
# the closed form the core uses.
