"""The progress bar on a terminal, and Ctrl-C during a long solve: the run ends as a refusal
(one error line, exit 1, no output file)."""

import os
import pty
import select
import signal
import subprocess
import time
import unittest

import cli_harness as h


class ProgressTest(unittest.TestCase):
    def test_bar_then_interrupt(self):
        d = h.workdir("progress")
        source, out = os.path.join(d, "big.off"), os.path.join(d, "out.off")
        h.write_off(source, *h.icosphere(6, 1.0))  # 40962 vertices: the paper's solver needs seconds
        master, slave = pty.openpty()
        proc = subprocess.Popen([h.tool(), "lowpass", "--solver", "pcg", "--s1", "1", "--s2", "2", "--tolerance", "1e-13",
                                 source, out], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave)
        os.close(slave)
        seen, deadline, interrupted = b"", time.time() + 60, False
        try:
            while True:
                if time.time() > deadline:
                    raise AssertionError(f"no progress bar within 60 s; the terminal got {seen!r}")
                ready, _, _ = select.select([master], [], [], 0.2)
                if ready:
                    try:
                        chunk = os.read(master, 4096)
                    except OSError:  # the tool closed the terminal: it has ended
                        break
                    if not chunk:
                        break
                    seen += chunk
                if not interrupted and b"solving" in seen and b"%" in seen:
                    proc.send_signal(signal.SIGINT)
                    interrupted = True
            proc.wait(timeout=30)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            os.close(master)
        self.assertTrue(interrupted, f"the bar never showed: {seen!r}")
        self.assertIn(b"geofilter: [#", seen)
        self.assertEqual(proc.returncode, 1, seen)
        # The bar is erased before the error line, which is the last thing printed.
        text = seen.decode(errors="replace")
        last_line = text.rstrip().rsplit("\r\x1b[K", 1)[-1]
        self.assertTrue(last_line.startswith("geofilter: error: cancelled by the user"), repr(text[-300:]))
        self.assertNotIn("\n", last_line)
        self.assertIn("\r\x1b[Kgeofilter: error:", text)
        self.assertFalse(os.path.exists(out))
        self.assertEqual([n for n in os.listdir(d) if n.startswith(".")], [])


if __name__ == "__main__":
    unittest.main()
