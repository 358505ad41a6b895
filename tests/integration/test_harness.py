"""The harness's parameter lists (FILTERS) against what the plugin declares to meshlabserver.

Together with the runs of test_filters.py (same count, a wrong name would abort; an extra
one is refused) this pins every name, type and the order of every GeoFilter parameter.
"""

import re
import unittest

import geofilter_harness as h

# Value::typeName() in MeshLab 2020.09, as printed by `meshlabserver -d`.
TYPE_NAMES = {"RichFloat": "Float", "RichBool": "Bool", "RichInt": "Int", "RichEnum": "Enum", "RichAbsPerc": "AbsPerc"}


class HarnessMatchesPlugin(unittest.TestCase):
    def test_dumped_filters_and_parameter_types_match_the_harness(self):
        text = h.dump_filters(h.workdir_for(self.id()))
        # One "\section fN <name>" per filter, then a table row per parameter.
        dumped = {}
        for section in re.split(r"^\\section f\d+ ", text, flags=re.M)[1:]:
            name = section.split("\n", 1)[0].strip()
            if name.startswith("GeoFilter"):
                dumped[name] = re.findall(r"<TR><TD> \\c (\w+)\s*</TD>", section)
        self.assertEqual(sorted(dumped), sorted(h.FILTERS), "GeoFilter filters known to meshlabserver")
        for name, params in h.FILTERS.items():
            with self.subTest(filter=name):
                self.assertEqual(dumped[name], [TYPE_NAMES[p.rich_type] for p in params])


if __name__ == "__main__":
    unittest.main()
