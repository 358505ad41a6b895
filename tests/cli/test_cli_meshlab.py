"""The face selection stored in PLY files, both ways between MeshLab 2020.09 and geofilter:
MeshLab saves a selection with face flags (meshlabserver -m ff) that --select-stored reads, and
MeshLab reads back the selection geofilter writes into its PLY output.

Needs meshlabserver ($GEOFILTER_MESHLABSERVER, else from PATH) and xvfb-run; fails when they
are missing (configuring with the test on, the default, fails when they are missing;
-DGEOFILTER_TEST_CLI_MESHLAB=OFF leaves it out explicitly)."""

import os
import re
import shutil
import signal
import subprocess
import unittest

import numpy as np

import cli_harness as h

SELECT_CAP = """<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Sphere">
  <Param name="radius" type="RichFloat" value="1"/>
  <Param name="subdiv" type="RichInt" value="3"/>
 </filter>
 <filter name="Conditional Face Selection">
  <Param name="condSelect" type="RichString" value="(z0 &gt;= 0.8) &amp;&amp; (z1 &gt;= 0.8) &amp;&amp; (z2 &gt;= 0.8)"/>
 </filter>
</FilterScript>
"""
DELETE_SELECTED = """<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Delete Selected Faces"/>
</FilterScript>
"""


def meshlabserver(workdir, script_text, args):
    server = os.environ.get("GEOFILTER_MESHLABSERVER") or shutil.which("meshlabserver")
    if not server or not shutil.which("xvfb-run"):
        raise AssertionError("meshlabserver or xvfb-run not found (apt install meshlab xvfb xauth)")
    script = os.path.join(workdir, "script.mlx")
    with open(script, "w") as f:
        f.write(script_text)
    cmd = ["xvfb-run", "-a", server, *args, "-s", script]
    proc = subprocess.Popen(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            errors="replace", start_new_session=True)
    try:
        out, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
    if proc.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{out[-2000:]}\n{err[-2000:]}")
    return err


class MeshLabSelectionTest(unittest.TestCase):
    def test_selection_round_trip(self):
        d = h.workdir("meshlab-selection")
        selected = os.path.join(d, "selected.ply")
        log = meshlabserver(d, SELECT_CAP, ["-o", selected, "-m", "ff"])
        count = int(re.search(r"selected (\d+) faces", log).group(1))
        self.assertGreater(count, 0)

        flags = h.read_ply(selected).face_flags
        self.assertIsNotNone(flags, "MeshLab wrote no face flags")
        self.assertEqual(int(np.count_nonzero(flags & 0x20)), count)

        stored = h.run("measure", "--select-stored", selected)
        self.assertEqual(stored.returncode, 0, h.describe(stored))
        self.assertIn(f"({count} faces)", stored.stdout)
        region = h.run("measure", "--select-box", "-2,-2,0.8,2,2,2", selected)
        self.assertEqual(region.returncode, 0, h.describe(region))
        self.assertEqual(stored.stdout.splitlines()[-1], region.stdout.splitlines()[-1])

        filtered = os.path.join(d, "filtered.ply")
        p = h.run("lowpass", "--select-stored", selected, filtered)
        self.assertEqual(p.returncode, 0, h.describe(p))
        total = len(h.read_ply(filtered).faces)
        pruned = os.path.join(d, "pruned.ply")
        log = meshlabserver(d, DELETE_SELECTED, ["-i", filtered, "-o", pruned])
        self.assertIn(f"Deleted {count} faces", log)
        self.assertEqual(len(h.read_ply(pruned).faces), total - count)


if __name__ == "__main__":
    unittest.main()
