"""The command line, run as a user runs it (subprocesses), and the README/CI contract."""

import re
import subprocess
import sys
from pathlib import Path

import warpoptics as wo
from warpoptics.film.image import read_image

ROOT = Path(__file__).resolve().parents[1]


def run_cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )


def test_version_and_info():
    r = run_cli("--version")
    assert r.returncode == 0 and r.stdout.strip() == f"warpoptics {wo.__version__}"
    r = run_cli("info")
    assert r.returncode == 0, r.stderr
    assert "warp" in r.stdout and "kernel cache" in r.stdout and "device         cpu" in r.stdout


def test_spectrum_image(tmp_path):
    out = tmp_path / "spectrum.png"
    r = run_cli("spectrum", "-o", str(out))
    assert r.returncode == 0, r.stderr
    assert "Smits–Meyer clip" in r.stdout
    img, _ = read_image(out)
    assert img.shape[0] > 200 and img.shape[1] > 600
    # the two strips are coloured (not blank): saturated pixels exist
    assert (img[..., :3].max(axis=-1) - img[..., :3].min(axis=-1)).max() > 0.5


def test_errors_are_one_line_without_traceback(tmp_path):
    r = run_cli("--device", "cuda:9", "info")
    assert r.returncode == 2
    assert "Traceback" not in r.stderr and "not available" in r.stderr
    r = run_cli("spectrum")  # missing -o
    assert r.returncode == 2 and "required" in r.stderr


def test_readme_and_ci_run_the_same_test_command():
    readme = (ROOT / "README.md").read_text()
    ci = (ROOT / ".ci" / "run").read_text()
    blocks = re.findall(r"```(?:bash|sh)?\n(.*?)```", readme, re.S)
    test_cmds = [line.strip() for b in blocks for line in b.splitlines() if "pytest" in line]
    assert test_cmds, "README shows no test command"
    cmd = test_cmds[0]
    assert cmd in ci, f"README's test command {cmd!r} is not what .ci/run runs"
    assert "set -euo pipefail" in ci


def test_quick_look_at_an_adaptive_scene(tmp_path):
    """``--spp 1`` on an adaptive scene (the main job's clear twin) samples every pixel once (no
    pilot fits below spp) and says so; asking for adaptive sampling with too few samples
    explicitly stays an error."""
    out = tmp_path / "d.png"
    small = ("render", "scenes/diamond_clear.toml", "-o", str(out), "--width", "24", "--height", "24")
    r = run_cli(*small, "--spp", "1", cwd=ROOT)
    assert r.returncode == 0, r.stderr
    assert "render.adaptive off: spp = 1" in r.stdout and "adaptive:" not in r.stdout.splitlines()[-1]
    assert read_image(out)[0].shape[:2] == (24, 24)
    r = run_cli(*small, "--set", "render.spp=2", cwd=ROOT)  # the same through --set
    assert r.returncode == 0 and "render.adaptive off: spp = 2" in r.stdout, r.stderr
    r = run_cli(*small, "--spp", "2", "--set", "render.adaptive=true", cwd=ROOT)
    assert r.returncode == 2 and "render.spp = 2" in r.stderr and "Traceback" not in r.stderr
