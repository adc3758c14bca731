"""The sweep's process pool when a worker dies: a worker SIGKILLed (what an out-of-memory kill
looks like) is noticed at once, its job runs again in a fresh worker, a job that kills its
worker every time is reported (a non-zero exit and a one-paragraph summary), and nothing hangs;
Ctrl-C on a pooled sweep prints one line and keeps the finished rows.

The pool tests use a cheap job function (this module's, imported by name in the workers); the
command-line tests run the real command as a subprocess on a tiny sweep (8x8 pixels, 4 jobs)
and find its workers among its child processes in /proc (Linux).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from warpoptics.sweep.backends import LostJob, pool_results

ROOT = Path(__file__).resolve().parents[1]
BOUND = 420  # seconds a whole subprocess sweep may take on a loaded 2-core machine (never a hang)

linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


def job(payload: dict) -> dict:
    """The pool tests' job: ``action`` "ok" returns, "die" SIGKILLs its own worker, "die_once"
    does so only the first time (a marker file remembers), "raise" raises a ValueError, "sleep"
    writes its marker file and sleeps 300 s."""
    action = payload["action"]
    if action == "die_once":
        marker = Path(payload["marker"])
        if not marker.exists():
            marker.write_text("died once")
            os.kill(os.getpid(), signal.SIGKILL)
    elif action == "die":
        os.kill(os.getpid(), signal.SIGKILL)
    elif action == "raise":
        raise ValueError(f"job {payload['job']['key']}: a bad value")
    elif action == "sleep":
        Path(payload["marker"]).write_text("started")
        time.sleep(300)
    return {"key": payload["job"]["key"], "pid": os.getpid()}


def _payloads(actions, tmp_path):
    return [
        {"action": a, "marker": str(tmp_path / f"marker{i}"), "job": {"key": f"k{i}", "index": i}}
        for i, a in enumerate(actions)
    ]


def test_pool_retries_a_lost_job_once_then_reports_it(tmp_path):
    payloads = _payloads(["ok", "die_once", "die", "ok", "ok"], tmp_path)
    t0 = time.monotonic()
    out = list(pool_results(job, payloads, 2, "process"))
    assert time.monotonic() - t0 < BOUND
    done = {r["key"] for r in out if isinstance(r, dict)}
    lost = [r for r in out if isinstance(r, LostJob)]
    assert done == {"k0", "k1", "k3", "k4"}  # k1's worker died once: run again, in a fresh worker
    assert (tmp_path / "marker1").read_text() == "died once"
    assert len(lost) == 1 and (lost[0].key, lost[0].index) == ("k2", 2)
    assert "killed by SIGKILL" in lost[0].reason and "tried 2 times" in lost[0].reason


def test_pool_raises_a_job_error_and_stops_its_workers(tmp_path):
    payloads = _payloads(["ok", "raise", "ok"], tmp_path)
    with pytest.raises(ValueError, match="job k1: a bad value"):
        list(pool_results(job, payloads, 2, "process"))
    import multiprocessing

    deadline = time.monotonic() + 30
    while multiprocessing.active_children() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not multiprocessing.active_children()  # every worker stopped and reaped


# -- the command ------------------------------------------------------------------------------
SCENE = """
[camera]
type = "orthographic"
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
view_height = 1.2
width = 8
height = 8

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
name = "pool"
scene = "scene.toml"

[[axis]]
name = "pav"
path = "object.0.pavilion_angle"
linspace = [39.0, 42.0, 4]

[[view]]
name = "dome"
metrics = ["light_return"]
"""


def _children(pid: int) -> list[tuple[int, str]]:
    """(pid, command line) of the processes whose parent is ``pid``."""
    found = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
            ppid = int(stat[stat.rindex(")") + 2 :].split()[1])
            if ppid == pid:
                found.append((int(d.name), (d / "cmdline").read_bytes().replace(b"\0", b" ").decode()))
        except (OSError, ValueError):
            continue
    return found


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie (a reaped or dead process is not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


def _rows(out: Path) -> int:
    try:
        return max(0, len((out / "results.csv").read_text().splitlines()) - 1)
    except OSError:
        return 0


def _start(tmp_path: Path, *extra: str, pool=("--workers", "2")) -> tuple[subprocess.Popen, Path]:
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "sweep.toml").write_text(SWEEP)
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    cmd = [sys.executable, "-m", "warpoptics.cli", "sweep", str(tmp_path / "sweep.toml"), "-o", str(out)]
    proc = subprocess.Popen(
        [*cmd, *pool, "--quiet", *extra],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal gives a command
    )
    return proc, out


def _finish(proc: subprocess.Popen, t0: float) -> tuple[str, str]:
    try:
        return proc.communicate(timeout=max(1.0, BOUND - (time.monotonic() - t0)))
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"the sweep did not end within {BOUND} s")


def _wait_for_first_row(proc, out, t0) -> None:
    while _rows(out) < 1:
        if proc.poll() is not None or time.monotonic() - t0 > BOUND:
            _finish(proc, t0)
            pytest.fail("no row was written")
        time.sleep(0.05)


@linux
def test_sweep_survives_a_worker_killed_after_the_first_row(tmp_path):
    """The failure as found: all rows written, then the parent waiting forever.  Now the killed
    worker's job runs again in a fresh worker and the sweep ends complete.  Killing Python's
    resource tracker as well prints no traceback."""
    t0 = time.monotonic()
    proc, out = _start(tmp_path)
    _wait_for_first_row(proc, out, t0)
    workers = [p for p, cmd in _children(proc.pid) if "spawn_main" in cmd]
    tracker = [p for p, cmd in _children(proc.pid) if "resource_tracker" in cmd]
    assert len(workers) >= 1
    os.kill(workers[0], signal.SIGKILL)
    for p in tracker:
        os.kill(p, signal.SIGKILL)
    stdout, stderr = _finish(proc, t0)
    assert proc.returncode == 0, stderr
    assert "4/4 jobs done" in stdout and _rows(out) == 4
    assert "Traceback" not in stderr


@linux
def test_sweep_reports_jobs_whose_workers_keep_dying(tmp_path):
    """Every worker killed as soon as it appears, after the first row: each job left is tried
    twice, then reported; the command exits 1 with one paragraph saying what is done, what
    failed and why, and where the results are.  A resume then completes the sweep."""
    t0 = time.monotonic()
    proc, out = _start(tmp_path)
    _wait_for_first_row(proc, out, t0)
    while proc.poll() is None and time.monotonic() - t0 < BOUND:
        for p, cmd in _children(proc.pid):
            if "spawn_main" in cmd:
                try:
                    os.kill(p, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        time.sleep(0.02)
    stdout, stderr = _finish(proc, t0)
    assert proc.returncode == 1, stderr
    assert "Traceback" not in stderr
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("warpoptics sweep: incomplete: ")
    done = _rows(out)
    assert 1 <= done < 4
    msg = lines[0]
    assert f"{done} of 4 rows done" in msg and str(out / "results.csv") in msg
    assert "killed by SIGKILL" in msg and "tried 2 times" in msg and "--resume" in msg
    assert f"{done}/4 jobs done" in stdout
    t1 = time.monotonic()
    proc, out = _start(tmp_path, "--resume")
    stdout, stderr = _finish(proc, t1)
    assert proc.returncode == 0, stderr
    assert f"4/4 jobs done ({4 - done} rendered now)" in stdout and _rows(out) == 4


@linux
@pytest.mark.parametrize("pool", [("--workers", "2"), ("--dask-local", "2")])
def test_ctrl_c_on_a_pooled_sweep_prints_one_line(tmp_path, pool):
    """SIGINT to the process group (Ctrl-C in a terminal) after the first row: one
    "interrupted" line (the workers, of the process pool or of a local Dask cluster, leave
    Ctrl-C to the parent: no traceback from each), status 130, the finished rows kept, and no
    worker left running."""
    if pool[0] == "--dask-local":
        pytest.importorskip("distributed")
    t0 = time.monotonic()
    proc, out = _start(tmp_path, pool=pool)
    _wait_for_first_row(proc, out, t0)
    workers = [p for p, cmd in _children(proc.pid) if "spawn_main" in cmd]
    os.killpg(proc.pid, signal.SIGINT)
    _stdout, stderr = _finish(proc, t0)
    assert proc.returncode == 130, stderr
    assert stderr.count("interrupted") == 1 and "Traceback" not in stderr
    assert _rows(out) >= 1
    deadline = time.monotonic() + 30
    while any(_alive(p) for p in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(_alive(p) for p in workers)


@linux
def test_workers_end_with_a_killed_sweep(tmp_path):
    """The sweep itself SIGKILLed (by the out-of-memory killer, say) while its workers are in
    jobs of 300 s: they do not run on for nobody, the kernel ends them with their parent."""
    payloads = _payloads(["sleep", "sleep"], tmp_path)
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import json\n"
        "from test_sweep_pool import job\n"
        "from warpoptics.sweep.backends import pool_results\n"
        "list(pool_results(job, json.loads(sys.argv[2]), 2, 'process'))\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    args = [sys.executable, "-c", code, str(Path(__file__).parent), json.dumps(payloads)]
    proc = subprocess.Popen(args, env=env, start_new_session=True)
    t0 = time.monotonic()
    while not all((tmp_path / f"marker{i}").exists() for i in range(2)):
        assert proc.poll() is None and time.monotonic() - t0 < BOUND, "the jobs did not start"
        time.sleep(0.05)
    workers = [p for p, cmd in _children(proc.pid) if "spawn_main" in cmd]
    assert len(workers) == 2
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=60)
    deadline = time.monotonic() + 30
    while any(_alive(p) for p in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(_alive(p) for p in workers)


@pytest.mark.parametrize("workers", [0, -1, 257, 10**6])
def test_workers_out_of_range_are_refused(tmp_path, workers):
    from warpoptics.errors import InputError
    from warpoptics.sweep import Sweep, SweepRunner

    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "sweep.toml").write_text(SWEEP)
    with pytest.raises(InputError, match=r"--workers = -?\d+: out of range \(allowed: 1 to 256\)"):
        SweepRunner(Sweep.load(tmp_path / "sweep.toml"), tmp_path / "out", workers=workers)
