"""(b) The MeshLab 2022+ plugin gives the 2020.09 plugin's results.

meshlab2022.write_cases (test_meshlab2022.cpp) ran every case through MeshLab 2022's
PluginManager and wrote cases.json: the input PLY, every parameter value, the selection
rule, the output PLY and the 2022 plugin's result map. Here each case is replayed with the
2020.09 plugin through the meshlabserver of the default build's private prefix (the
integration tests' harness), and the outputs are compared: same faces, coordinates equal
within single precision.
"""

import json
import os
import re
import unittest

import numpy as np

import geofilter_harness as h  # tests/integration, on PYTHONPATH through ctest

# Both plugins run the same double-precision core on the same float input; what may differ is
# only how each MeshLab rounds parameters and results to its scalar type. 16 float epsilons
# of the mesh size leaves room for that and nothing else.
FLOAT_EPS = float(np.finfo(np.float32).eps)
TOLERANCE = 16 * FLOAT_EPS


def load_cases():
    path = os.environ.get("GEOFILTER_CASES")
    if not path or not os.path.isfile(path):
        raise AssertionError(f"no cases file ({path!r}): run meshlab2022.write_cases first (ctest -L meshlab2022)")
    with open(path) as f:
        cases = json.load(f)
    if not cases:
        raise AssertionError(f"{path} lists no cases")
    return cases


class Compare2020(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cases = load_cases()
        h.check_environment()   # fails, never skips, without the 2020.09 prefix or xvfb-run

    def run_2020(self, case):
        d = h.workdir_for(f"compare.{case['tag']}")
        steps = []
        if "select_above" in case:
            c = repr(float(case["select_above"]))
            steps.append(h.select_faces(f"(z0 > {c}) && (z1 > {c}) && (z2 > {c})"))
        # Built from the case (the filter table as the 2022 plugin saw it), not from the
        # harness's own parameter lists, so that both runs state exactly the same values.
        params = [(h.Param(p["name"], p["type"], p["value"], p["choices"]), p["value"]) for p in case["params"]]
        steps.append(h.Step(case["filter"], params))
        out = os.path.join(d, "out2020.ply")
        layer = "x" if case["measure"] else None   # the measure's product is its new (last) layer
        run = h.run_meshlabserver(d, steps, inputs=[case["input"]], outputs=[(out, layer)])
        self.assertEqual(run.returncode, 0, run.describe())
        return run, h.read_ply(out)

    def test_every_case_matches(self):
        worst = {}
        for case in self.cases:
            with self.subTest(case=case["tag"]):
                run, old = self.run_2020(case)
                new = h.read_ply(case["output"])
                inp = h.read_ply(case["input"])
                np.testing.assert_array_equal(new.faces, old.faces)
                self.assertEqual(new.vertices.shape, old.vertices.shape)
                scale = np.linalg.norm(inp.vertices.max(axis=0) - inp.vertices.min(axis=0))
                diff = np.max(np.abs(new.vertices - old.vertices)) / scale
                worst[case["tag"]] = diff
                self.assertLessEqual(diff, TOLERANCE,
                                     f"{case['tag']}: max difference {diff:.3g} of the input's size "
                                     f"(tolerance {TOLERANCE:.3g})")
                if not case["measure"]:
                    # The filter did something: otherwise equality would prove nothing.
                    self.assertGreater(np.max(np.abs(new.vertices - inp.vertices)) / scale, 1e-4)
                else:
                    self.check_measure_results(case, run)
        print("\nmax |2022 - 2020| / input size, per case:")
        for tag, d in worst.items():
            print(f"  {tag:24s} {d:.3g}  ({d / FLOAT_EPS:.2f} float eps)")

    def check_measure_results(self, case, run):
        # The 2022 result map against the numbers 2020.09 logs (5 significant digits).
        line = next((l for l in run.log if ": feature: " in l), None)
        self.assertIsNotNone(line, run.describe())
        # The line also states the ellipsoid's axes (an eigenvector's sign is arbitrary, so they are
        # not compared here; test_meshlab2022.cpp checks the result map's): radii, centre and r.
        m = re.search(r"ellipsoid radii ([^,]+), ([^,]+), ([^;]+); centre \(([^,]+), ([^,]+), ([^)]+)\); "
                      r"(?:axes [^;]*; )?feature radius r = ([^ ]+)", line)
        self.assertIsNotNone(m, line)
        logged = [float(x) for x in m.groups()]
        res = case["results"]
        got = res["radii"] + res["centre"] + [res["radius"]]
        for a, b in zip(got, logged):
            self.assertAlmostEqual(a, b, delta=1e-4 * max(1.0, abs(b)), msg=line)
        r = res["radius"]
        np.testing.assert_allclose(res["frequencies"], [2 / r ** 2, 1 / r ** 2], rtol=1e-9)


if __name__ == "__main__":
    unittest.main()
