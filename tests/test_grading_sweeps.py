"""Cut grading on the sweep runner: the full protocol (fire, scintillation), the tilt series
(SIGKILL + resume and a local Dask cluster, through the CLI), the cut optimizer (journal replay,
constraints, best.asc), the `warpoptics grade` command, and the gallery scripts in --quick mode.

Renders are tiny (12-32 px, 2-4 wavelengths); each check compares against an independent
construction (the in-process protocol, a closed-form volume, the GemCAD file read back).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from _helpers import ROOT

from warpoptics.errors import InputError
from warpoptics.geometry import gemcad
from warpoptics.geometry.cuts import cube, round_brilliant
from warpoptics.grading.performance import PROTOCOL, average_views, brightness_map, tilted_light_return
from warpoptics.sweep.grading import (
    light_performance,
    protocol_scores,
    protocol_sweep,
    protocol_views,
    renders_per_job,
)
from warpoptics.sweep.optimize import Constraints, CutOptimizer, Parameter
from warpoptics.sweep.results import read_results

DIAMOND = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", "table": 0.55}
TINY = dataclasses.replace(PROTOCOL, tilts=(0.0, 10.0), azimuths=(0.0,), size=16, wavelengths=2)


def env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    return e


def cli(*args, timeout=300):
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", *map(str, args)],
        env=env(),
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def main_(capsys, *args):
    """The command in this process (no interpreter start-up): (exit code, stdout, stderr)."""
    from warpoptics.cli import main

    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_brightness_map_closed_form():
    y = np.array([[1.0, 0.6, 0.3, 0.1]])
    xyz = np.stack([y, y, y], axis=-1)
    a = np.ones_like(y)
    _img, fr, rel = brightness_map(xyz, a)
    assert fr == pytest.approx({"bright": 0.5, "medium": 0.25, "dark": 0.25})
    np.testing.assert_allclose(rel, y)
    # a coloured stone: every pixel 5x darker.  Against white all but one go dark; against the
    # stone's own 95th percentile (its brightest pixel here) the classes are those above
    _img, fr_w, _ = brightness_map(0.2 * xyz, a)
    _img, fr_s, rel_s = brightness_map(0.2 * xyz, a, reference="stone")
    assert fr_w["dark"] == pytest.approx(0.75) and fr_s == pytest.approx(fr)
    np.testing.assert_allclose(rel_s, y, rtol=1e-12)
    with pytest.raises(InputError, match="reference"):
        brightness_map(xyz, a, reference="sun")


def test_protocol_definitions():
    views = protocol_views(TINY)
    assert [v.name for v in views] == ["iso_t00_a00", "spots_t00_a00", "iso_t10_a00", "spots_t10_a00"]
    sw = protocol_sweep(DIAMOND, TINY)
    assert renders_per_job(sw) == 2 * 3  # per view: ISO, spots, spots turned a further step
    assert renders_per_job(protocol_sweep(DIAMOND, TINY, fire=False)) == 2
    row = {f"{v.name}_{m}": str(k + j) for k, v in enumerate(views) for j, m in enumerate(v.metrics)}
    s = protocol_scores(row, TINY)
    # iso views are columns 0 and 2 (light_return = 0 + 0, 2 + 0), spots 1 and 3 (fire 1, 3)
    assert s["light_return"] == pytest.approx(1.0) and s["fire"] == pytest.approx(2.0)
    assert s["scintillation"] == pytest.approx(3.0) and s["extinction"] == pytest.approx(3.0)
    with pytest.raises(InputError, match="tilts"):
        dataclasses.replace(PROTOCOL, tilts=(0.0, 95.0))
    with pytest.raises(InputError, match="different metrics"):
        average_views([{"a": 1.0}, {"b": 1.0}])


def test_full_protocol_matches_in_process_protocol():
    # the sweep path (rotation set by a view override) and the in-process protocol (rotation set
    # by face_up_scene) render the same scenes: the same light return, contrast and extinction
    r = light_performance(DIAMOND, TINY)
    ref = tilted_light_return(DIAMOND, TINY)
    for k in ("light_return", "contrast", "extinction"):
        assert r[k] == pytest.approx(ref[k], rel=1e-12, abs=1e-12), k
    assert r["renders"] == 6 and r["fire"] > 0 and 0 < r["scintillation"] <= 1


def test_constraints_weight_retention_closed_form():
    # a cube of edge a: V = a^3, rough = pi/4 a * a * (2a) (rough_height 2): retention 2/pi
    c = Constraints(min_weight_retention=0.7, rough_height=2.0, depth=(0.5, 0.9))
    m = c.measure(cube(size=3.0))
    assert m["weight_retention"] == pytest.approx(2 / math.pi, rel=1e-9)
    assert m["depth"] == pytest.approx(1.0)
    # violations: (0.7 - 2/pi) / 0.7 for the weight, (1 - 0.9) / 0.9 for the depth
    want = (0.7 - 2 / math.pi) / 0.7 + 0.1 / 0.9
    assert c.violation(m) == pytest.approx(want, rel=1e-9)
    assert Constraints().violation(m) == 0.0
    with pytest.raises(InputError, match="depth"):
        Constraints(depth=(0.7, 0.5))


def _optimizer(out, **kw):
    proto = dataclasses.replace(TINY, tilts=(0.0,), size=12)
    params = [
        Parameter("pavilion", "object.0.pavilion_angle", 38.0, 44.0, 43.0),
        Parameter("crown", "object.0.crown_angle", 25.0, 40.0, 30.0),
    ]
    return CutOptimizer(DIAMOND, params, out, protocol=proto, budget=12, popsize=6, **kw)


def test_optimizer_journal_resume_and_design(tmp_path):
    out = tmp_path / "opt"
    # total depth 0.55-0.62 cuts off the deep and high-crowned corner of the box: never rendered
    cons = Constraints(depth=(0.55, 0.62))
    r = _optimizer(out, constraints=cons).run()
    _h, rows = read_results(out / "journal.csv")
    feas = [x for x in rows if x["feasible"] == "true"]
    assert r["evaluations"] == len(feas) <= 12 and r["renders_this_run"] == len(feas) * 1
    for x in rows:  # the depth is the cut's own, and infeasible rows carry no metrics
        d = (
            round_brilliant(
                diameter=6.5, table=0.55, pavilion_angle=float(x["pavilion"]), crown_angle=float(x["crown"])
            )
            .metadata["proportions"]
            .total_depth
        )
        assert float(x["depth"]) == pytest.approx(d, rel=1e-9)
        assert (x["feasible"] == "true") == (0.55 <= d <= 0.62)
        if x["feasible"] == "false":
            assert x["light_return"] == "" and int(x["renders"]) == 0
    best = max(feas, key=lambda x: float(x["objective"]))
    assert r["best"]["objective"] == pytest.approx(float(best["objective"]))
    # best.asc: the best cut's pavilion mains and bezels, read back from the GemCAD file
    design = gemcad.read_design(out / "best.asc")
    angles = {round(abs(t.angle), 3) for t in design.tiers}
    assert round(float(best["pavilion"]), 3) in angles and round(float(best["crown"]), 3) in angles
    for f in ("report.md", "report.json", "trace.png", "parameters.png"):
        assert (out / f).is_file(), f
    # resume: the search replays from the journal, renders nothing and ends the same
    again = _optimizer(out, constraints=cons, resume=True).run()
    assert again["renders_this_run"] == 0 and again["best"]["values"] == r["best"]["values"]
    assert read_results(out / "journal.csv")[1] == rows
    with pytest.raises(InputError, match="--resume"):
        _optimizer(out, constraints=cons).run()
    with pytest.raises(InputError, match="other settings"):
        _optimizer(out, constraints=cons, resume=True, seed=7).run()
    with pytest.raises(InputError, match="unknown metric"):
        _optimizer(tmp_path / "x", objective={"sparkle": 1.0})


def _rows(path):
    return [r.split(",") for r in path.read_text().splitlines()]


def test_tilt_series_sigkill_resume_and_dask(tmp_path, capsys):
    # killed with SIGKILL after 3 of 10 jobs, resumed on a local Dask cluster of 2: the kept
    # rows are not rendered again, and the table (kept rows + the rows Dask rendered) equals a
    # serial run in this process (deterministic renders)
    pytest.importorskip("distributed")
    from warpoptics.sweep.grading import tilt_series

    out = tmp_path / "tilt"
    n = 10
    args = ["grade", "tilt", "round_brilliant", "--size", "12", "--wavelengths", "2", "--quiet"]
    args += ["--tilts", f"0:{n - 1}:1", "--azimuths", "0", "-o", out, "--resume"]
    cmd = [sys.executable, "-m", "warpoptics.cli", *map(str, args)]
    proc = subprocess.Popen(cmd, env=env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t0 = time.monotonic()
    while proc.poll() is None and time.monotonic() - t0 < 120:
        if len(read_results(out / "results.csv")[1]) >= 3:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=60)
    proc.stderr.close()
    kept = len(read_results(out / "results.csv")[1])
    assert 3 <= kept < n and not (out / "tilt_series.csv").exists()
    code, stdout, stderr = main_(capsys, *args, "--dask-local", "2")  # the resume: in this process
    assert code == 0, stderr
    assert f"{n - kept} jobs rendered now" in stdout  # the kept rows were not rendered again
    table = _rows(out / "tilt_series.csv")
    assert table[0] == ["azimuth", "tilt", "light_return", "contrast", "extinction", "fire", "scintillation"]
    assert [float(r[1]) for r in table[1:]] == list(range(n))
    from PIL import Image

    with Image.open(out / "tilt_series.gif") as gif:
        assert gif.n_frames == n + (n - 2)  # there and back
    assert (out / "tilt_series.png").stat().st_size > 0
    proto = dataclasses.replace(PROTOCOL, size=12, wavelengths=2)
    stone = {"shape": "round_brilliant", "diameter": 6.5}
    tilt_series(stone, tmp_path / "local", tilts=range(n), azimuths=(0,), protocol=proto, progress=False)
    assert _rows(out / "tilt_series.csv") == _rows(tmp_path / "local" / "tilt_series.csv")


def test_grade_cli_scopes_and_errors(tmp_path, capsys):
    code, out, err = main_(
        capsys, "grade", "aset", "round_brilliant", "--set", "pavilion_angle=43", "--size", "24",
        "-o", tmp_path / "a.png",
    )  # fmt: skip
    assert code == 0, err
    z = json.loads((tmp_path / "a.json").read_text())["zones"]
    assert sum(z[k] for k in ("blue", "red", "green", "leak")) == pytest.approx(1.0)
    assert f"leak {z['leak']:.3f}" in out
    assert 0.0 <= z["area_leak_crown"] <= 1.0 and "area_leak_centre" in z
    code, out, err = main_(
        capsys, "grade", "hearts", "round_brilliant", "--face-down", "--size", "32", "-o", tmp_path / "h.png",
    )  # fmt: skip
    assert code == 0, err
    h = json.loads((tmp_path / "h.json").read_text())
    assert h["hearts"] in (8, None) and len(h["per_ring"]) == 7 and h["verdict"] in out
    srb = ROOT / "tests/data/gemcad/SRB.asc"
    code, out, err = main_(capsys, "grade", "retarget", srb, "--index", "1.544", "-o", tmp_path / "q.asc")
    assert code == 0, err
    assert gemcad.read_design(tmp_path / "q.asc").index == pytest.approx(1.544)
    for bad, field in (
        (("aset", "nonsense", "-o", tmp_path / "x.png"), "STONE"),
        (("aset", "round_brilliant", "-o", tmp_path / "x.jpg"), "-o"),
        (("optimize", "round_brilliant", "-o", tmp_path / "o", "--param", "pavilion_angle=44"), "--param"),
        (("tilt", "round_brilliant", "-o", tmp_path / "t", "--tilts", "a,b"), "--tilts"),
        (("retarget", "round_brilliant", "--index", "1.5", "-o", tmp_path / "r.asc"), "STONE"),
    ):
        code, _out, err = main_(capsys, "grade", *bad)
        lines = [ln for ln in err.splitlines() if "CUDA" not in ln]
        assert code == 2 and len(lines) == 1 and field in lines[0], err


def test_grade_optimize_and_report_cli(tmp_path, capsys):
    common = [
        "--size",
        "12",
        "--wavelengths",
        "2",
        "--quiet",
        "--protocol-tilts",
        "0",
        "--protocol-azimuths",
        "0",
    ]
    code, out, err = main_(
        capsys, "grade", "optimize", "round_brilliant", *common, "--param", "pavilion_angle=39:43:42",
        "--budget", "8", "--popsize", "4", "-o", tmp_path / "opt",
    )  # fmt: skip
    assert code == 0, err
    assert "best: pavilion_angle" in out and (tmp_path / "opt" / "best.asc").is_file()
    code, out, err = main_(capsys, "grade", "report", "round_brilliant", *common, "-o", tmp_path / "rep")
    assert code == 0, err
    rep = json.loads((tmp_path / "rep" / "report.json").read_text())
    assert rep["renders"] == 3 and 0 < rep["light_return"] < 1 and rep["fire"] >= 0
    assert f"{rep['light_return']:.4f}" in (tmp_path / "rep" / "report.md").read_text()


def _script(path):
    import importlib.util

    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize(
    "script", ["grading_gallery.py", "grading_tilt_animation.py", "grading_optimizer_trace.py"]
)
def test_gallery_scripts_quick(script, tmp_path):
    # in this process (the scripts' main(argv)); the same code the lead runs without --quick
    assert _script(ROOT / "scripts" / "reproduce" / script).main(["--quick", "-o", str(tmp_path)]) == 0
    assert any(p.suffix in (".png", ".gif") for p in tmp_path.rglob("*"))


def test_bench_optimizer_quick(tmp_path):
    bench = _script(ROOT / "scripts" / "bench" / "bench_optimizer.py")
    assert bench.main(["--quick", "--out", str(tmp_path)]) == 0
    d = json.loads((tmp_path / "bench_optimizer.json").read_text())
    # counted renders: 3 x 3 sweep jobs of one view each; whole optimizer generations of 6
    assert d["sweep"]["renders"] == 9 and d["optimizer"]["renders"] == 6
    assert d["ratio_best"] > 0 and (tmp_path / "bench_optimizer.png").is_file()
