"""Drives the GeoFilter MeshLab 2020.09 plugin through the private prefix's meshlabserver.

meshlabserver 2020.09 aborts on a script that omits a parameter (and refuses one with an
extra parameter), so every script lists EVERY parameter of a GeoFilter filter. The lists
(FILTERS below) come from the build's filter table; test_harness.py checks them against
what the plugin declares.
"""

import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np
import filter_table
from reference_design import eq15_gain  # noqa: F401 (used as harness.eq15_gain)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_PREFIX = os.path.join(HERE, "..", "..", "build", "meshlab-prefix")
PLUGIN_RELDIR = os.path.join("lib", "x86_64-linux-gnu", "meshlab", "plugins")


# ---------------------------------------------------------------------------------------------
# The parameter lists of the GeoFilter filters, in the plugin's order, from the filter table
# the build wrote (filter_table.py). Defaults are the table's but for the harness's own two
# choices: useSelection off (a test selects explicitly) and a tighter solver tolerance.

@dataclass(frozen=True)
class Param:
    name: str
    rich_type: str  # RichFloat, RichBool, RichInt, RichEnum, RichAbsPerc
    default: object
    choices: int = 0  # RichEnum only: number of choices (enum_cardinality)


HARNESS_DEFAULTS = {"useSelection": False, "tolerance": 1e-10}


def _param(spec):
    kind = spec["type"]
    default = HARNESS_DEFAULTS.get(spec["name"], spec["default"])
    if kind == "Bool":
        default = bool(default)
    elif kind in ("Int", "Enum"):
        default = int(default)
    elif kind == "Length":
        # The table gives a fraction of the diagonal; the plugin turns it into a length on the
        # current mesh. A script can only give lengths, so a nonzero default is left out and
        # meshlabserver takes it from the plugin (see geofilter()).
        return Param(spec["name"], "RichAbsPerc", None if default else 0.0)
    return Param(spec["name"], "Rich" + kind, default, len(spec["choices"]) if kind == "Enum" else 0)


FILTERS = {f["name"]: [_param(p) for p in f["parameters"]] for f in filter_table.TABLE}
SECOND_ORDER = [f["name"] for f in filter_table.TABLE if f["kind"] == "SecondOrder"]


# ---------------------------------------------------------------------------------------------
# Script steps

@dataclass
class Step:
    filter: str
    params: list = field(default_factory=list)  # [(Param, value)]


def geofilter(name, **values):
    """A GeoFilter step with every parameter: the table's value unless given. A length whose
    default depends on the mesh (the feature radius, always the first parameter) is left out
    unless given: meshlabserver 2020.09 fills in one missing parameter, the first, with the
    plugin's default on the current mesh, as it does for a script from an older version."""
    spec = FILTERS[name]
    known = {p.name for p in spec}
    unknown = set(values) - known
    if unknown:  # a typo here would otherwise surface as a meshlabserver abort
        raise KeyError(f"{name} has no parameter(s) {sorted(unknown)}")
    return Step(name, [(p, values.get(p.name, p.default)) for p in spec
                       if p.name in values or p.default is not None])


def sphere(radius, subdiv):
    """filter_create's icosphere (icosahedron subdivided `subdiv` times, projected)."""
    return Step("Sphere", [(Param("radius", "RichFloat", 1.0), radius), (Param("subdiv", "RichInt", 3), subdiv)])


def select_faces(condition):
    """filter_func's Conditional Face Selection (muparser: x0..z2, fi, ...)."""
    return Step("Conditional Face Selection", [(Param("condSelect", "RichString", ""), condition)])


def vertex_quality(function):
    """filter_func's Per Vertex Quality Function (muparser: x, y, z, ...), not normalised."""
    return Step("Per Vertex Quality Function",
                [(Param("q", "RichString", "vi"), function), (Param("normalize", "RichBool", False), False),
                 (Param("map", "RichBool", False), False), (Param("onselected", "RichBool", False), False)])


def _value_text(p, v):
    if p.rich_type == "RichBool":
        if not isinstance(v, bool):
            raise TypeError(f"{p.name}: RichBool wants True/False, got {v!r}")
        return "true" if v else "false"
    if p.rich_type in ("RichInt", "RichEnum"):
        return str(int(v))
    if p.rich_type in ("RichFloat", "RichAbsPerc"):
        return repr(float(v))
    return str(v)


def write_script(path, steps):
    root = ET.Element("FilterScript")
    for s in steps:
        f = ET.SubElement(root, "filter", name=s.filter)
        for p, v in s.params:
            if p.rich_type == "RichPoint3f":  # a point is written as three attributes, no value
                ET.SubElement(f, "Param", name=p.name, type=p.rich_type, x=repr(float(v[0])), y=repr(float(v[1])),
                              z=repr(float(v[2])))
                continue
            e = ET.SubElement(f, "Param", name=p.name, type=p.rich_type, value=_value_text(p, v))
            if p.rich_type == "RichAbsPerc":  # the range only scales the dialog's percentage
                e.set("min", "0")
                e.set("max", repr(max(1.0, 10 * float(v))))
            if p.rich_type == "RichEnum":
                e.set("enum_cardinality", str(p.choices))
                for i in range(p.choices):
                    e.set(f"enum_val{i}", f"choice {i}")
    ET.indent(root, space=" ")
    with open(path, "w", encoding="utf-8") as out:
        out.write("<!DOCTYPE FilterScript>\n" + ET.tostring(root, encoding="unicode") + "\n")


# ---------------------------------------------------------------------------------------------
# Running meshlabserver

def prefix():
    return os.path.abspath(os.environ.get("GEOFILTER_MESHLAB_PREFIX", DEFAULT_PREFIX))


def check_environment():
    """Fails (never skips) when the prefix or the X server wrapper is missing."""
    p = prefix()
    server = os.path.join(p, "bin", "meshlabserver")
    plugin = os.path.join(p, PLUGIN_RELDIR, "libfilter_geofilter.so")
    problems = []
    if not os.access(server, os.X_OK):
        problems.append(f"no meshlabserver at {server}")
    if not os.path.isfile(plugin):
        problems.append(f"no plugin at {plugin}")
    if shutil.which("xvfb-run") is None:
        problems.append("xvfb-run not found (apt install xvfb xauth)")
    if problems:
        raise AssertionError("integration test environment broken: " + "; ".join(problems) +
                             ". Build it with: cmake --build build --target filter_geofilter")
    return server


@dataclass
class Run:
    returncode: int
    stdout: str
    stderr: str
    command: list

    @property
    def log(self):
        """The filters' log lines: meshlabserver echoes each as 'LOG: <level> <text>' on stderr."""
        return [m.group(1) for m in re.finditer(r"^LOG: \d+ (.*)$", self.stderr, re.M)]

    def describe(self):
        return (f"command: {' '.join(self.command)}\nexit code: {self.returncode}\n"
                f"--- stdout ---\n{self.stdout[-4000:]}\n--- stderr ---\n{self.stderr[-4000:]}")


XVFB_CLEANUP_FAILED = "xvfb-run: error: problem while cleaning up temporary directory"


def run_meshlabserver(workdir, steps, inputs=(), outputs=(), timeout=120, script_name="script.mlx"):
    """Runs a script. outputs: [(path, layer)] with layer None (current), 'x' (last) or an int."""
    server = check_environment()
    script = os.path.join(workdir, script_name)
    write_script(script, steps)
    cmd = ["xvfb-run", "-a", server]
    for i in inputs:
        cmd += ["-i", i]
    cmd += ["-s", script]
    for path, layer in outputs:
        cmd += ["-o", path]
        if layer is not None:
            cmd += ["-l", str(layer)]
    for attempt in range(2):
        # A session of its own, so a hung run can be killed with its Xvfb.
        proc = subprocess.Popen(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                errors="replace", start_new_session=True)
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            raise AssertionError(f"meshlabserver timed out after {timeout} s\n" + Run(-1, out, err, cmd).describe())
        # xvfb-run exits 5 when it cannot remove its own temporary directory after the command
        # ran, and the command's exit status is lost (seen once in a test run with two tests at
        # a time): that says nothing of meshlabserver, so the script is run once more.
        if not (proc.returncode == 5 and XVFB_CLEANUP_FAILED in err):
            break
        print(f"xvfb-run could not clean up after {script}; running it again", file=sys.stderr)
    base = os.path.splitext(script)[0]  # kept next to the script, for inspection
    with open(base + ".out", "w") as f:
        f.write(out)
    with open(base + ".err", "w") as f:
        f.write(err)
    return Run(proc.returncode, out, err, cmd)


def dump_filters(workdir, timeout=120):
    """`meshlabserver -d`: every filter with its help and the type and label of each parameter."""
    server = check_environment()
    path = os.path.join(workdir, "filters-dump.txt")
    p = subprocess.run(["xvfb-run", "-a", server, "-d", path], cwd=workdir, capture_output=True, text=True,
                       errors="replace", timeout=timeout)
    if p.returncode != 0 or not os.path.isfile(path):
        raise AssertionError(f"meshlabserver -d failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read()


def workdir_for(test_id):
    """A fresh folder per test: under GEOFILTER_TEST_WORKDIR (kept for inspection) or /tmp."""
    base = os.environ.get("GEOFILTER_TEST_WORKDIR")
    if not base:
        return tempfile.mkdtemp(prefix="geofilter-it-")
    d = os.path.join(base, re.sub(r"[^A-Za-z0-9_.-]", "_", test_id))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def run_to_mesh(test, tag, steps):
    """Runs `steps` for a TestCase in a fresh folder and reads the current layer back; fails
    the test (with meshlabserver's output) if meshlabserver fails. Returns (run, mesh)."""
    d = workdir_for(f"{test.id()}.{tag}")
    out = os.path.join(d, "out.ply")
    run = run_meshlabserver(d, steps, outputs=[(out, None)])
    test.assertEqual(run.returncode, 0, run.describe())
    return run, read_ply(out)


# ---------------------------------------------------------------------------------------------
# PLY

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


@dataclass
class PlyMesh:
    vertices: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int


def read_ply(path):
    """Vertices and triangles of a PLY as VCG writes it (ascii or binary little endian)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = None
    elements = []  # (name, count, [(prop, type, list_count_type or None)])
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            if w[1] == "list":
                elements[-1][2].append((w[4], w[3], w[2]))
            else:
                elements[-1][2].append((w[2], w[1], None))
    body = data[end:]
    verts = faces = None
    if fmt == "ascii":
        tokens = body.split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for pname, ptype, ltype in props:
                    if ltype:
                        k = int(tokens[pos]); pos += 1
                        row[pname] = [int(t) for t in tokens[pos:pos + k]]; pos += k
                    else:
                        row[pname] = float(tokens[pos]); pos += 1
                rows.append(row)
            if name == "vertex":
                # Round as the declared type would (MeshLab reads "float" into float32).
                ptype = _PLY_TYPES[dict((n, t) for n, t, _ in props)["x"]]
                verts = np.array([[r["x"], r["y"], r["z"]] for r in rows], dtype=ptype).reshape(-1, 3)
                verts = verts.astype(np.float64)
            elif name == "face":
                faces = np.array([r["vertex_indices"] for r in rows], dtype=np.int64).reshape(-1, 3)
    elif fmt == "binary_little_endian":
        pos = 0
        for name, count, props in elements:
            # All VCG faces here are triangles: a list of 3 lets one fixed-size dtype read them.
            dt = []
            for pname, ptype, ltype in props:
                if ltype:
                    dt += [(pname + "_n", "<" + _PLY_TYPES[ltype]), (pname, "<" + _PLY_TYPES[ptype], (3,))]
                else:
                    dt.append((pname, "<" + _PLY_TYPES[ptype]))
            arr = np.frombuffer(body, dtype=np.dtype(dt), count=count, offset=pos)
            pos += arr.nbytes
            if name == "vertex":
                verts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
            elif name == "face":
                if count and not np.all(arr["vertex_indices_n"] == 3):
                    raise ValueError(f"{path}: non-triangular faces")
                faces = arr["vertex_indices"].astype(np.int64).reshape(-1, 3)
    else:
        raise ValueError(f"{path}: unsupported PLY format {fmt}")
    if verts is None or faces is None:
        raise ValueError(f"{path}: no vertex or face element")
    return PlyMesh(verts, faces)


def write_ply_ascii(path, mesh):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(mesh.vertices)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(mesh.faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in mesh.vertices:
            f.write("%.9g %.9g %.9g\n" % tuple(v))
        for t in mesh.faces:
            f.write("3 %d %d %d\n" % tuple(t))


def radii(vertices, center=None):
    c = vertices.mean(axis=0) if center is None else center
    return np.linalg.norm(vertices - c, axis=1)


# ---------------------------------------------------------------------------------------------
# Eq. 15 comes from the shared test reference, tests/support/reference_design.py (on
# PYTHONPATH through ctest): its five conditions solved as a linear system, never a copy of
# the closed form the core uses.


# Eq. 16, whose product form needs no solving.

def eq16_gain(s, G0, zeros, poles):
    """Eq. 16: G0 * (prod p / prod z) * prod (s + z) / prod (s + p), unused corners (0) dropped."""
    zeros = [z for z in zeros if z > 0]
    poles = [p for p in poles if p > 0]
    g = G0 * np.prod(poles) / np.prod(zeros)
    return g * np.prod([s + z for z in zeros]) / np.prod([s + p for p in poles])
