"""Sweeps: definitions, expressions, resumable execution (SIGKILL mid-run), Dask, CLI.

Renders are tiny (16x16, 3 wavelengths, depth 3) so that the whole file runs in well under a
minute on a warm kernel cache.  The expected tables come from an uninterrupted in-process run:
renders are deterministic, so every backend and every interrupted-and-resumed run must give
the same rows (timing columns aside).
"""

from __future__ import annotations

import csv
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from warpoptics.errors import InputError
from warpoptics.sweep import (
    Axis,
    Sweep,
    SweepRunner,
    View,
    apply_overrides,
    evaluate_expression,
    read_results,
)

ROOT = Path(__file__).resolve().parents[1]

SCENE = """
[camera]
type = "orthographic"
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
view_height = 1.2
width = 16
height = 16

[render]
spectral = "stratified"
wavelengths = 3
max_depth = 3

[[light]]
type = "environment"
map = "dome"

[[object]]
shape = "round_brilliant"
diameter = 1.0
material = "diamond"
"""

SWEEP = """
name = "tiny"
scene = "scene.toml"
label = "pavilion {pav:.1f}"

[[axis]]
name = "pav"
path = "object.0.pavilion_angle"
linspace = [39.0, 42.0, 6]

[expr]
"object.0.crown_angle" = "34.5 + (pav - 40.75) * 0.5"

[[view]]
name = "dome"
metrics = ["color", "light_return"]

[compare]
axis = "pav"
reference = 39.0
"""

TIMING = ("seconds",)


def write_sweep(folder: Path, sweep_text: str = SWEEP) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "scene.toml").write_text(SCENE)
    p = folder / "sweep.toml"
    p.write_text(sweep_text)
    return p


def table(path: Path) -> list[dict]:
    _h, rows = read_results(path)
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    return e


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted in-process run of the tiny sweep: (sweep file, result, table)."""
    d = tmp_path_factory.mktemp("ref")
    sw_path = write_sweep(d)
    result = SweepRunner(Sweep.load(sw_path), d / "out", progress=False).run()
    return sw_path, result, table(d / "out" / "results.csv")


# -- definitions -------------------------------------------------------------------------------


def test_expressions():
    v = {"size_mm": 0.1, "kk": True}
    assert evaluate_expression("0.3 * 10 / size_mm", v) == pytest.approx(30.0)
    assert evaluate_expression("[0.0, -22.0 * size_mm, sqrt(4)]", v) == [0.0, -22.0 * 0.1, 2.0]
    assert evaluate_expression("1 if kk and size_mm < 1 else 2", v) == 1
    assert evaluate_expression("{'base': 'diamond', 'kramers_kronig': kk}", v) == {
        "base": "diamond",
        "kramers_kronig": True,
    }
    assert evaluate_expression("max(1, 2) ** 2 + degrees(pi)", v) == pytest.approx(184.0)
    for bad, msg in [
        ("sise_mm * 2", "did you mean 'size_mm'"),
        ("().__class__", "unsupported syntax"),
        ("__import__('os')", "unknown function"),
        ("1 / 0", "cannot evaluate"),
        ("1 +", "not a valid expression"),
    ]:
        with pytest.raises(InputError, match=msg):
            evaluate_expression(bad, v)


@pytest.mark.parametrize(
    "text, msg",
    [
        ("9**9**9", "integers are limited to 4096 bits"),  # 9**387420489: 370 million digits
        ("3999999**3999999", "integers are limited"),  # passes an operand-size guard like simpleeval's
        ("2**4096 * 2**4096", "integers are limited"),
        ("[0]*10**9", "more than 100000 elements"),  # 8 GB of list
        ('"a"*10**10', "more than 100000 elements"),  # 10 GB of string
        ("[[0]*1000]*1000", "more than 100000 elements"),  # shared rows still count: JSON-dumped for the key
        ("'%0999999999d' % 1", "string formatting"),  # a 1 GB string from a 1-char result
        ("round(5, -10**9)", "round\\(\\) takes at most 400 digits"),  # CPython computes 10**10**9
        ("[" * 150 + "]" * 150, "nested too deeply"),
        ("-" * 1500 + "1", "nested too deeply"),  # our recursive walk would overflow the C stack
        ("1+" * 900 + "1", "nested too deeply"),
        ("1+" * 1500 + "1", "limited to 2000 characters"),
    ],
)
def test_expressions_refuse_what_would_hang_or_exhaust_memory(text, msg):
    # Each is refused with the field and the expression named, before the work
    # is done.  A refusal takes microseconds (the unguarded evaluation: minutes, or the memory);
    # one second is a bound that a loaded CI machine meets and a hang does not.
    t0 = time.perf_counter()
    with pytest.raises(InputError, match=msg) as info:
        evaluate_expression(text, {}, file="s.toml", field_name="expr.big")
    assert time.perf_counter() - t0 < 1.0
    assert str(info.value).startswith("s.toml: expr.big = ")
    assert text[:40] in str(info.value)


def test_expressions_within_the_bounds_still_work():
    # the bounds are inclusive limits, not a change of meaning: values at them evaluate exactly
    assert evaluate_expression("2**4095", {}) == 1 << 4095
    assert evaluate_expression("[0]*99999", {}) == [0] * 99999
    assert evaluate_expression("round(2.5, 400)", {}) == 2.5
    assert evaluate_expression("'%.3f' if x else 0", {"x": False}) == 0
    assert evaluate_expression("1+" * 60 + "1", {}) == 61
    assert evaluate_expression("2.0**-10**9", {}) == 0.0  # a float power is one libm call


def test_product_zip_groups_and_keys(tmp_path):
    (tmp_path / "scene.toml").write_text(SCENE)
    a = Axis("a", (1.0, 2.0), path="object.0.pavilion_angle")
    b = Axis("b", (10.0, 20.0, 30.0))
    c = Axis("c", (100.0, 200.0, 300.0), group="g")
    d = Axis("d", (7, 8, 9), group="g")
    base = dict(scene="scene.toml", base_dir=tmp_path)
    prod = Sweep(axes=(a, b), **base).jobs()
    assert [(j.values["a"], j.values["b"]) for j in prod] == [
        (1.0, 10.0),
        (1.0, 20.0),
        (1.0, 30.0),
        (2.0, 10.0),
        (2.0, 20.0),
        (2.0, 30.0),
    ]
    assert prod[0].overrides == {"object.0.pavilion_angle": 1.0}  # b sets nothing: a variable only
    zipped = Sweep(axes=(b, c), mode="zip", **base).jobs()
    assert [(j.values["b"], j.values["c"]) for j in zipped] == [(10.0, 100.0), (20.0, 200.0), (30.0, 300.0)]
    grouped = Sweep(axes=(a, c, d), **base).jobs()
    assert len(grouped) == 6 and {(j.values["c"], j.values["d"]) for j in grouped} == {
        (100.0, 7),
        (200.0, 8),
        (300.0, 9),
    }
    with pytest.raises(InputError, match="same number of values"):
        Sweep(axes=(a, b), mode="zip", **base)
    # keys: stable, unique, and they change when a job's overrides change
    again = Sweep(axes=(a, b), **base).jobs()
    assert [j.key for j in prod] == [j.key for j in again] and len({j.key for j in prod}) == 6
    changed = Sweep(axes=(a, b), set={"render.spp": 2}, **base).jobs()
    assert not {j.key for j in changed} & {j.key for j in prod}
    # Python callables as per-job expressions
    sw = Sweep(axes=(b,), expr={"object.0.diameter": lambda v: v["b"] / 10}, **base)
    assert [j.overrides["object.0.diameter"] for j in sw.jobs()] == [1.0, 2.0, 3.0]


def test_toml_definition_and_errors(tmp_path):
    p = write_sweep(tmp_path)
    sw = Sweep.load(p)
    jobs = sw.jobs()
    assert [j.values["pav"] for j in jobs] == [39.0, 39.6, 40.2, 40.8, 41.4, 42.0]
    assert jobs[0].label == "pavilion 39.0"
    assert jobs[4].overrides["object.0.crown_angle"] == pytest.approx(34.5 + (41.4 - 40.75) * 0.5)
    assert sw.columns() == ["X", "Y", "Z", "L", "a", "b", "C", "h", "coverage", "light_return"]
    sw.validate(jobs)
    for text, msg in [
        (SWEEP.replace('name = "pav"', 'nmae = "pav"'), "did you mean 'name'"),
        (SWEEP.replace("reference = 39.0", "reference = 38.0"), "must be one of the axis values"),
        (SWEEP.replace('"color", "light_return"', '"colour"'), "did you mean 'color'"),
        (SWEEP.replace('scene = "scene.toml"', 'scene = "nope.toml"'), "base scene file not found"),
        (SWEEP.replace('"34.5 + (pav - 40.75) * 0.5"', '"34.5 + pavilion"'), "unknown name 'pavilion'"),
    ]:
        bad = write_sweep(tmp_path / "bad", text)
        with pytest.raises(InputError, match=msg):
            Sweep.load(bad).jobs()
    # a bad scene value fails validation, before any rendering
    bad = write_sweep(
        tmp_path / "bad2", SWEEP.replace('path = "object.0.pavilion_angle"', 'path = "object.0.pavillion"')
    )
    sw = Sweep.load(bad)
    with pytest.raises(InputError, match="pavilion_angle"):
        sw.validate()


def test_material_paths_make_inline_tables():
    data = {"object": [{"shape": "sphere", "material": "spinel"}]}
    out = apply_overrides(
        data, {"object.0.material.kramers_kronig": True, "object.0.material.absorption_rgb": [0.1, 0.2, 0.3]}
    )
    assert out["object"][0]["material"] == {
        "base": "spinel",
        "kramers_kronig": True,
        "absorption_rgb": [0.1, 0.2, 0.3],
    }
    assert data["object"][0]["material"] == "spinel"  # the input is not modified
    data = {"object": [{"shape": "sphere", "material": {"base": "diamond", "bands": [{"center_nm": 550.0}]}}]}
    out = apply_overrides(data, {"object.0.material.bands.0.peak_alpha_per_mm": 3.0})
    assert out["object"][0]["material"]["bands"][0] == {"center_nm": 550.0, "peak_alpha_per_mm": 3.0}


def test_results_file_torn_last_line(tmp_path):
    p = tmp_path / "results.csv"
    p.write_text("index,key,x\n0,k0,1.5\n1,k1,2.5\n2,k2,3")  # the last row was cut short
    header, rows = read_results(p)
    assert header == ["index", "key", "x"] and [r["key"] for r in rows] == ["k0", "k1"]
    assert p.read_text().endswith(",3")  # reading alone changes nothing
    read_results(p, repair=True)
    assert p.read_text() == "index,key,x\n0,k0,1.5\n1,k1,2.5\n"
    p.write_text("index,key,x\n0,k0\n")  # a complete line with too few fields is ignored too
    assert read_results(p)[1] == []
    assert read_results(tmp_path / "missing.csv") == (None, [])


# -- execution ---------------------------------------------------------------------------------


def test_local_run_outputs_and_resume(reference, tmp_path):
    sw_path, result, rows = reference
    out = result.out_dir
    assert [r["index"] for r in rows] == [str(i) for i in range(6)]
    assert len(result.pairs) == 5 and all(p["dE_mean"] >= 0 for p in result.pairs)
    for j in result.jobs:
        assert (out / "images" / f"{j.key}.exr").is_file() and (out / "images" / f"{j.key}.png").is_file()
    for name in (
        "contact_sheet.png",
        "summary.md",
        "pairs.csv",
        "sweep.json",
        "plots/light_return_vs_pav.png",
        "plots/dE_mean_vs_pav.png",
    ):
        assert (out / name).is_file(), name
    assert "light_return" in (out / "summary.md").read_text()
    lr = [float(r["light_return"]) for r in rows]
    assert all(0.0 < v < 1.0 for v in lr)
    # rerun: nothing to render; without --resume a folder with results is refused
    again = SweepRunner(Sweep.load(sw_path), out, resume=True, progress=False).run()
    assert again.rendered == 0 and table(out / "results.csv") == rows
    with pytest.raises(InputError, match="--resume"):
        SweepRunner(Sweep.load(sw_path), out, progress=False).run()
    # a thread pool gives the same table
    t = SweepRunner(
        Sweep.load(sw_path), tmp_path / "threads", workers=2, executor="thread", progress=False
    ).run()
    assert t.rendered == 6 and table(tmp_path / "threads" / "results.csv") == rows


def test_sigkill_and_resume(reference, tmp_path):
    """Kill the CLI with SIGKILL at random points, resume until done: every row exactly once."""
    sw_path, _result, rows = reference
    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "warpoptics.cli",
        "sweep",
        str(sw_path),
        "-o",
        str(out),
        "--resume",
        "--quiet",
    ]
    rng = random.Random(1234)
    kills = 0
    for _attempt in range(3):
        before = len(read_results(out / "results.csv")[1])
        proc = subprocess.Popen(cmd, env=env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        target = before + rng.randint(1, 2)
        t0 = time.monotonic()
        while proc.poll() is None and time.monotonic() - t0 < 120:
            if len(read_results(out / "results.csv")[1]) >= target:
                time.sleep(rng.uniform(0.0, 0.3))  # land somewhere inside the next job
                break
            time.sleep(0.02)
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            kills += 1
        proc.wait(timeout=60)
        if proc.returncode == 0:
            break
        assert proc.returncode == -signal.SIGKILL, proc.stderr.read().decode()
        proc.stderr.close()
        done = read_results(out / "results.csv")[1]
        keys = [r["key"] for r in done]
        assert len(keys) == len(set(keys))  # never a duplicate, even mid-run
    assert kills >= 1
    res = subprocess.run(cmd, env=env(), capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    got = table(out / "results.csv")
    assert [r["key"] for r in got] == [r["key"] for r in rows]  # every job exactly once, in order
    assert got == rows  # and the same numbers as the uninterrupted run
    assert (out / "summary.md").is_file() and (out / "contact_sheet.png").is_file()
    # no temporary files left behind by the atomic writes... except those of killed writes
    assert all(p.suffix in (".exr", ".png") for p in (out / "images").iterdir() if not p.name.startswith("."))


def test_dask_local_cluster_same_table(reference, tmp_path):
    pytest.importorskip("distributed")
    sw_path, _result, rows = reference
    r = SweepRunner(Sweep.load(sw_path), tmp_path / "dask", dask_local=2, progress=False).run()
    assert r.rendered == 6
    assert table(tmp_path / "dask" / "results.csv") == rows
    # the images too: bit-identical renders
    from warpoptics.film.image import read_image

    for j in r.jobs[:2]:
        a, _ = read_image(tmp_path / "dask" / "images" / f"{j.key}.exr")
        b, _ = read_image(reference[1].out_dir / "images" / f"{j.key}.exr")
        assert np.array_equal(a, b)


def test_scintillation_and_fire_views(tmp_path):
    """A job with two views: fire and scintillation columns, per-view files; fire_excess of a
    stone without dispersion is exactly 0 (its twin is the same render: same camera samples)."""
    (tmp_path / "scene.toml").write_text(SCENE)
    studio = View(
        "studio",
        set={"light.0.map": "studio"},
        metrics=("fire", "fire_excess", "scintillation"),
        tilts=((3.0, 0.0, 0.0),),
    )
    sw = Sweep(
        scene="scene.toml",
        base_dir=tmp_path,
        axes=(
            Axis("mat", ("diamond", {"cauchy": [2.4175]}), path="object.0.material", labels=("d", "flat")),
        ),
        views=(View("dome", metrics=("light_return",)), studio),
    )
    r = SweepRunner(sw, tmp_path / "out", progress=False).run()
    assert sw.columns() == [
        "dome_light_return",
        "studio_fire",
        "studio_fire_nondispersive",
        "studio_fire_excess",
        "studio_scintillation",
    ]
    diamond, flat = r.rows
    assert 0.0 < float(diamond["studio_scintillation"]) < 1.0 and float(diamond["studio_fire"]) > 0.0
    assert float(flat["studio_fire_excess"]) == 0.0
    assert float(flat["studio_fire"]) == float(flat["studio_fire_nondispersive"]) > 0.0  # sampling colour
    assert (tmp_path / "out" / "images" / f"{r.jobs[0].key}.studio.exr").is_file()


# -- command line ------------------------------------------------------------------------------


def test_cli(tmp_path, capsys):
    from warpoptics.cli import main

    sw_path = write_sweep(tmp_path)
    out = str(tmp_path / "o")
    # in-process: --list, and the refusal to write into a folder with results without --resume
    assert main(["sweep", str(sw_path), "-o", out, "--list"]) == 0
    assert capsys.readouterr().out.count("pavilion") == 6
    bad = tmp_path / "bad.toml"
    bad.write_text(SWEEP.replace('name = "tiny"', 'name = "tiny"\nmode = "grid"'))
    assert main(["sweep", str(bad), "-o", out]) == 2
    err = capsys.readouterr().err
    assert "mode" in err and "product, zip" in err
    # as a subprocess: a whole run with --set overrides
    cmd = [
        sys.executable,
        "-m",
        "warpoptics.cli",
        "sweep",
        str(sw_path),
        "-o",
        out,
        "--quiet",
        "--set",
        "camera.width=8",
        "--set",
        "camera.height=8",
    ]
    res = subprocess.run(cmd, env=env(), capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "6/6 jobs done" in res.stdout and "paired CIEDE2000" in res.stdout
    with open(tmp_path / "o" / "results.csv", newline="") as f:
        assert len(list(csv.DictReader(f))) == 6
    from warpoptics.film.image import read_image

    assert read_image(next((tmp_path / "o" / "images").glob("*.exr")))[0].shape[:2] == (8, 8)
    assert main(["sweep", str(sw_path), "-o", out, "--quiet"]) == 2
    assert "--resume" in capsys.readouterr().err
