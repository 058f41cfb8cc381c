"""The examples run from a clean build: the paper's Figure 4 from Python, saved as a PNG."""

import os
import subprocess
import sys

from conftest import ROOT


def test_the_link_bandwidth_figure_is_made_end_to_end(tmp_path):
    out = tmp_path / "figure4.png"
    p = subprocess.run([sys.executable, os.path.join(ROOT, "examples", "link_bandwidth.py"), "--scenes",
                        "courtyard,oa:no_such_map", "--resolution", "320x240", "--out", str(out)],
                       capture_output=True, text=True, env=dict(os.environ))
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 10000
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "the paper    baseline      0.35     0.58     0.78" in p.stdout
    assert "courtyard    oo-vr" in p.stdout
    assert "plot: " in p.stdout
