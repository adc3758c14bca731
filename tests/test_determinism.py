"""Determinism: the rendered EXR is byte-identical for any thread count."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
from _helpers import ROOT

from warpoptics.film.image import read_image


def test_cli_render_is_byte_identical_for_any_thread_count(tmp_path):
    scene = ROOT / "scenes" / "calcite.toml"
    outs = []
    for threads in ("1", "2"):
        out = tmp_path / f"t{threads}.exr"
        env = {**os.environ, "PYTHONPATH": str(ROOT), "WARPOPTICS_THREADS": threads}
        p = subprocess.run(
            [
                sys.executable,
                "-m",
                "warpoptics.cli",
                "render",
                str(scene),
                "-o",
                str(out),
                "--width",
                "12",
                "--height",
                "10",
                "--quiet",
                "--set",
                "render.wavelengths=4",
            ],
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
        )
        assert p.returncode == 0, p.stderr
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    px, names = read_image(tmp_path / "t1.exr")
    assert "S3" in names and np.isfinite(px).all() and px[..., names.index("Y")].max() > 0
