"""The cut optimizer on a local Dask cluster (``--dask-local 2``): the same journal and design as
a serial run with the same seed, and a run killed with SIGKILL resumes without rendering a
finished evaluation again (its Dask workers, watching their parent, exit by themselves).

Two parameters (pavilion, crown), face-up only, 16 px, 2 wavelengths, 3 generations of 4: each
evaluation is one render, so renders count evaluations.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
from _helpers import ROOT

from warpoptics.sweep.results import read_results

pytest.importorskip("distributed")

ARGS = [
    "grade", "optimize", "round_brilliant",
    "--param", "pavilion_angle=38:44:43", "--param", "crown_angle=25:40:30",
    "--size", "16", "--wavelengths", "2", "--protocol-tilts", "0", "--protocol-azimuths", "0",
    "--budget", "12", "--popsize", "4", "--seed", "3", "--quiet",
]  # fmt: skip


def _env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    return e


def _cmd(*extra) -> list[str]:
    return [sys.executable, "-m", "warpoptics.cli", *ARGS, *map(str, extra)]


def _feasible(path) -> int:
    return sum(1 for r in read_results(path)[1] if r["feasible"] == "true")


def _group_gone(pgid: int, timeout: float = 30.0) -> bool:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.05)
    return False


def test_optimizer_dask_equals_serial_and_resumes_after_sigkill(tmp_path, capsys):
    from warpoptics.cli import main

    serial = tmp_path / "serial"
    assert main([*ARGS, "-o", str(serial)]) == 0, capsys.readouterr().err
    capsys.readouterr()
    rep_serial = json.loads((serial / "report.json").read_text())
    assert rep_serial["evaluations"] == 12 and rep_serial["renders_this_run"] == 12

    out = tmp_path / "dask"
    # its own session: its process group holds its Dask workers (checked to exit after the kill)
    proc = subprocess.Popen(
        _cmd("--dask-local", 2, "-o", out),
        env=_env(),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    t0 = time.monotonic()
    journal = out / "journal.csv"
    while proc.poll() is None and time.monotonic() - t0 < 240:
        if journal.is_file() and _feasible(journal) >= 4:  # the first generation is journaled
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run finished before it could be killed: " + proc.stderr.read().decode()
    os.kill(proc.pid, signal.SIGKILL)  # the command only, as a machine's OOM killer would
    proc.wait(timeout=60)
    proc.stderr.close()
    gone = _group_gone(proc.pid, timeout=60)
    if not gone:
        os.killpg(proc.pid, signal.SIGKILL)  # the workers of the command started above
    assert gone, "a Dask worker outlived the killed command"
    assert not (out / "report.json").exists()
    journaled = _feasible(journal)
    generations = sorted((out / "generations").iterdir())
    # evaluations of the generation cut short: rows of its sweep, not yet in the journal
    partial = sum(len(read_results(g / "results.csv")[1]) for g in generations[journaled // 4 :])
    finished = journaled + partial
    assert 4 <= finished < 12

    # the resume in this process (no interpreter start-up), on a new local cluster of 2
    assert main([*ARGS, "--dask-local", "2", "--resume", "-o", str(out)]) == 0, capsys.readouterr().err
    rep = json.loads((out / "report.json").read_text())
    assert rep["evaluations"] == 12
    assert rep["renders_this_run"] == 12 - finished  # no finished evaluation rendered again
    # the same search and the same numbers as the serial run (renders independent of threads)
    assert journal.read_text() == (serial / "journal.csv").read_text()
    assert (out / "best.asc").read_bytes() == (serial / "best.asc").read_bytes()
    assert rep["best"] == rep_serial["best"]
