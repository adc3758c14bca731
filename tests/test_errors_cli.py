"""The command line on bad input: one line on stderr, exit 2, no traceback."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from _helpers import ROOT

from warpoptics import cli

# ---- the command line: one line on stderr, exit 2, no traceback (in-process for speed) ----------

CLI_CASES = [
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--width", "0"], "camera.width = 0"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--spp", "0"], "render.spp = 0"),
    (["render", "{scene}", "-o", "{tmp}/a.bmp"], "unsupported output format"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--width", "100000", "--height", "100000"], "GiB"),
    (["render", "{tmp}/missing.toml", "-o", "{tmp}/a.exr"], "scene file not found"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "render.spp"], "expected KEY=VALUE"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "object.0.diamter=5"], "did you mean 'diameter'"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "render.spp=abc"], "render.spp = 'abc'"),
    (["render", "{scene}", "-o", "/dev/null/a.exr", "--width", "2"], "cannot create the output"),
    (["bench", "{tmp}/missing.toml", "-o", "{tmp}/b.png"], "scene file not found"),
    (["bench", "{scene}", "-o", "{tmp}/b.png"], "camera: unknown key"),
    (["cut", "round_brilliant", "-o", "{tmp}/c.xyz"], "unsupported output format"),
    (["cut", "roundbrilliant", "-o", "{tmp}/c.ply"], "unknown shape"),
    (["cut", "round_brilliant", "--pavilion-angle", "80", "-o", "{tmp}/c.ply"], "pavilion_angle = 80.0"),
    (["cut", "round_brilliant", "--apex-angle", "30", "-o", "{tmp}/c.ply"], "not a parameter"),
    (["cut", "{tmp}/missing.asc", "-o", "{tmp}/c.ply"], "no such file"),
    (["cut", "step_cut", "--crown-angles", "30,x", "-o", "{tmp}/c.ply"], "comma-separated"),
    (["material", "diamnod"], "did you mean 'diamond'"),
    (["material", "diamond", "--plot", "{tmp}/m.xyz"], "unsupported plot format"),
    (["spectrum", "-o", "{tmp}/s.xyz"], "unsupported plot format"),
    (["--device", "bogus", "info"], "not available"),
    (["thinfilm", "table", "-o", "{tmp}/t.xyz"], "unsupported output type"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--count", "100000000"], "--count = 100000000"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--model", "exact", "--n-film", "0.5"], "--n-film = 0.5"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--multilayer", "--d1", "-3"], "--d1 = -3.0"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--multilayer", "--layers", "0"], "--layers = 0"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--illuminant", "X99"], "unknown illuminant"),
]


@pytest.mark.parametrize(
    ("argv", "match"), CLI_CASES, ids=[" ".join(c[0][:2]) + f"-{i}" for i, c in enumerate(CLI_CASES)]
)
def test_cli_bad_input_one_line_exit_2(tmp_path, capsys, monkeypatch, argv, match):
    monkeypatch.setenv("WARPOPTICS_DEVICE", "cpu")  # restored afterwards ("--device bogus" sets it)
    scene = str(ROOT / "scenes" / "diamond.toml")
    args = [a.format(scene=scene, tmp=tmp_path) for a in argv]
    rc = cli.main(args)
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("warpoptics")]
    assert rc == 2, err
    assert len(lines) == 1 and match in lines[0], err
    assert "Traceback" not in err


def test_cli_unwritable_output_is_one_line(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    rc = cli.main(["cut", "cube", "-o", str(blocker / "sub" / "c.ply")])
    err = capsys.readouterr().err
    assert rc == 2 and "Traceback" not in err and err.count("\n") == 1, err


def test_cli_subprocess_exit_code_and_debug(tmp_path):
    """The real command: one line, exit 2, no traceback; ``--debug`` (even after the subcommand)
    shows the traceback."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    base = [
        sys.executable,
        "-m",
        "warpoptics.cli",
        "render",
        str(ROOT / "scenes" / "diamond.toml"),
        "-o",
        str(tmp_path / "a.exr"),
        "--set",
        "render.sp=2",
    ]
    p = subprocess.run(base, capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 2
    ours = [ln for ln in p.stderr.splitlines() if ln.startswith("warpoptics")]
    assert len(ours) == 1 and "render.sp: unknown key; did you mean 'spp'?" in ours[0], p.stderr
    assert "Traceback" not in p.stderr
    p = subprocess.run([*base, "--debug"], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode != 0 and "Traceback" in p.stderr and "InputError" in p.stderr
