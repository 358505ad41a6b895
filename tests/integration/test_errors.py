"""(d) Refusals: meshlabserver must fail and the log must say why, naming the parameter.

meshlabserver stops the script at the failing filter and saves nothing, so "the mesh is
unchanged on error" cannot be observed here (the unit tests cover it); what is checked is
the exit code and the "GeoFilter error:" line the plugin logs (meshlabserver does not
print errorMessage).
"""

import os
import unittest

import geofilter_harness as h

FAILED = 255  # meshlabserver's exit(-1) after "Failed to apply script file"


class Refusals(unittest.TestCase):
    def expect_failure(self, tag, steps, *needles):
        d = h.workdir_for(f"{self.id()}.{tag}")
        out = os.path.join(d, "out.ply")
        run = h.run_meshlabserver(d, steps, outputs=[(out, None)])
        self.assertEqual(run.returncode, FAILED, "expected a clean failure (not a crash)\n" + run.describe())
        errors = [l for l in run.log if l.startswith("GeoFilter error: ")]
        self.assertEqual(len(errors), 1, run.describe())
        for n in needles:
            self.assertIn(n, errors[0], run.describe())
        self.assertIn("Problem with filter: " + steps[-1].filter, run.stdout, run.describe())
        self.assertFalse(os.path.exists(out), "a failed script must not save a mesh")
        return errors[0]

    def test_G1_equal_to_1(self):
        self.expect_failure("G1", [h.sphere(1, 2), h.geofilter("GeoFilter: Custom", useSelection=False, G1=1.0)],
                            "G1 must differ from 1")

    def test_negative_s1(self):
        self.expect_failure("s1", [h.sphere(1, 2), h.geofilter("GeoFilter: Lowpass", useSelection=False, s1=-1.0)],
                            "s1 and s2 must be finite frequencies >= 0")

    def test_negative_pole(self):
        self.expect_failure("p2", [h.sphere(1, 2), h.geofilter("GeoFilter: Pole-Zero", useSelection=False, p2=-5.0)],
                            "p2")

    def test_unstable_design(self):
        # docs/paper-notes.md §4: this "highpass" has denominator roots at s = 18 and 52.
        self.expect_failure("unstable", [h.sphere(1, 2), h.geofilter("GeoFilter: Custom", useSelection=False,
                                                                     s1=25.0, s2=10.0, G0=1.0, G1=3.0, Ginf=0.0)],
                            "unstable")

    def test_use_selection_without_selection(self):
        self.expect_failure("nosel", [h.sphere(1, 2), h.geofilter("GeoFilter: Lowpass", useSelection=True)],
                            "no faces are selected", "useSelection")

    def test_measure_without_selection(self):
        self.expect_failure("measure", [h.sphere(1, 2), h.geofilter("GeoFilter: Measure Selected Feature")],
                            "no faces are selected")

    def test_wrong_parameter_type_is_refused_not_an_abort(self):
        # MeshLab's getters assert on a type mismatch; the plugin checks first.
        step = h.geofilter("GeoFilter: Lowpass", useSelection=False)
        step.params = [(h.Param(p.name, "RichInt", 0), 1) if p.name == "useSelection" else (p, v) for p, v in step.params]
        self.expect_failure("type", [h.sphere(1, 2), step], "useSelection", "RichBool")

    def test_missing_parameter_aborts(self):
        # Documents the meshlabserver 2020.09 behaviour that makes FILTERS list every parameter.
        d = h.workdir_for(f"{self.id()}")
        step = h.geofilter("GeoFilter: Lowpass", useSelection=False)
        step.params = step.params[:-1]
        run = h.run_meshlabserver(d, [h.sphere(1, 2), step])
        self.assertNotEqual(run.returncode, 0, run.describe())


if __name__ == "__main__":
    unittest.main()
