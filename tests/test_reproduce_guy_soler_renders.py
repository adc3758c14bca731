"""The Guy & Soler 2004 picture reproductions run as subprocesses with ``--quick`` (24 px panels)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "scripts" / "reproduce"


def _run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, *map(str, args)], capture_output=True, text=True, env=env, timeout=600, check=False
    )


@pytest.mark.parametrize(
    "script, marker",
    [
        ("guy_soler_fig3_pleochroism.py", "axis left-right"),
        ("guy_soler_sec61_gems.py", "andalusite"),
        ("guy_soler_fig11_garnet_depth.py", "3 internal refl."),
        ("guy_soler_fig11_andalusite.py", "dE00"),
        ("guy_soler_fig8_dispersion.py", "mean dE00 spectral vs rgb3"),
    ],
)
def test_guy_soler_picture_script(tmp_path, script, marker):
    out = tmp_path / "fig.png"
    r = _run(SCRIPTS / script, "--quick", "-o", out, "--device", "cpu")
    assert r.returncode == 0, r.stderr
    assert marker in r.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    if "garnet" in script:
        row = next(ln for ln in r.stdout.splitlines() if ln.startswith("converged"))
        assert float(row.split()[-3]) == pytest.approx(1.0)  # the converged panel is its own reference


def test_bad_size_is_refused(tmp_path):
    r = _run(SCRIPTS / "guy_soler_fig8_dispersion.py", "--size", "3", "-o", tmp_path / "x.png")
    assert r.returncode != 0 and "--size" in r.stderr
