"""Frame times of `warpoptics view`: the first frame, refining, orbiting, a cut change.

Starts the real command (``python -m warpoptics.cli view SCENE --port 0``) as a subprocess and
talks to it over HTTP from this process exactly as the page does (GET /frame.jpg, POST
/controls), so the times include the pass, the JPEG encoding and the transfer.  Once per draft
scale (``--draft-scales``, default ``2,1``: the default half-resolution draft after each change,
then none):

* ``startup_to_first_frame_s``: from launching the command to the first frame received (Python
  imports, scene, Renderer, one pass) — needs the kernel cache warm (run once before);
* ``first_frame_s``: from the server being up (it prints its URL) to the first frame received
  (the draft where there is one), ``first_full_frame_s`` to the first full-resolution one;
* ``first_whole_pass_s``: to the first frame with a whole full-resolution pass in (pixel
  beams come in bands of rows, a frame each);
* refining: frames of the unchanged view (each one more full-resolution pass, or beams' band);
* orbiting: before every frame the azimuth moves by ``--orbit-step`` degrees (a restart each
  time, so every frame is the draft — or pass 1 — of a new view): the frame rate while dragging;
* ``cut_change_s``: a pavilion-angle change (the Renderer is rebuilt: new mesh) to its first frame.

CPU seconds of the server process (``/proc/PID/stat``) are reported beside wall seconds: on a
busy machine the wall figures drift, CPU seconds per frame much less.

    python scripts/bench/bench_view.py --json scripts/bench/results/bench_view_400x300.json \\
        2>&1 | tee scripts/bench/results/bench_view_400x300.log
    python scripts/bench/bench_view.py --quick     # a smoke run (64x48, a few frames; seconds)
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
TIMEOUT = 600.0  # seconds for the server to come up (a cold kernel cache compiles for minutes)


def _cpu_seconds(pid: int) -> float:
    """utime + stime of a process (its threads included), from /proc."""
    with open(f"/proc/{pid}/stat", encoding="ascii") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _get(url: str) -> tuple[dict, bytes]:
    with urllib.request.urlopen(url, timeout=120) as r:
        return dict(r.headers), r.read()


def _token(base: str) -> str:
    """The launch's write token, from the served page's ``warpoptics-token`` meta tag (what the
    page's own script sends: the server takes writes only from its page)."""
    _, page = _get(base)
    m = re.search(rb'<meta name="warpoptics-token" content="([^"]+)">', page)
    if m is None:
        raise RuntimeError("the preview page carries no write token")
    return m.group(1).decode("ascii")


def _post(url: str, values: dict) -> dict:
    base = url.rsplit("/", 1)[0] + "/"
    if base not in _TOKENS:
        _TOKENS[base] = _token(base)
    headers = {
        "Content-Type": "application/json",
        "Origin": base.rstrip("/"),
        "X-Warpoptics-Token": _TOKENS[base],
    }
    req = urllib.request.Request(url, data=json.dumps(values).encode(), method="POST", headers=headers)
    with urllib.request.urlopen(req, timeout=120) as r:
        return json.loads(r.read())


_TOKENS: dict[str, str] = {}


def _frames(url: str, n: int, pid: int, before=None) -> dict:
    """``n`` frames, each after ``before(i)`` (if given): wall intervals and server CPU seconds."""
    times, headers = [], []
    c0 = _cpu_seconds(pid)
    t0 = time.perf_counter()
    last = t0
    for i in range(n):
        if before is not None:
            before(i)
        h, _ = _get(url + "frame.jpg")
        now = time.perf_counter()
        times.append(now - last)
        last = now
        headers.append(h)
    wall = time.perf_counter() - t0
    cpu = _cpu_seconds(pid) - c0
    return {
        "frames": n,
        "wall_s": wall,
        "frames_per_s": n / wall,
        "median_frame_s": float(np.median(times)),
        "max_frame_s": float(np.max(times)),
        "server_cpu_s_per_frame": cpu / n,
        "headers": headers,
    }


def measure(args, draft_scale: int) -> dict:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    cmd = [sys.executable, "-m", "warpoptics.cli", "view", args.scene, "--port", "0"]
    cmd += ["--width", str(args.width), "--height", str(args.height), "--draft-scale", str(draft_scale)]
    t_launch = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    try:
        url = None
        deadline = time.monotonic() + TIMEOUT
        assert proc.stdout is not None
        while time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            if line.startswith("warpoptics view: http://"):
                url = line.split()[2]
                break
        if url is None:
            raise RuntimeError(f"the viewer did not start:\n{proc.stderr.read() if proc.stderr else ''}")
        t_ready = time.perf_counter()
        headers, _ = _get(url + "frame.jpg")
        t_first = time.perf_counter()
        while headers["X-Draft"] == "1":
            headers, _ = _get(url + "frame.jpg")
        t_full = time.perf_counter()
        # pixel beams come in bands of rows, a frame each: the first whole pass takes many frames
        while int(headers["X-Passes"]) < 1:
            headers, _ = _get(url + "frame.jpg")
        t_pass = time.perf_counter()
        state = json.loads(_get(url + "state")[1])
        values = {c["name"]: c["value"] for c in state["controls"]}
        refining = _frames(url, args.frames, proc.pid)
        az0 = float(values["azimuth"])

        def orbit(i: int) -> None:
            _post(url + "controls", {"azimuth": az0 + args.orbit_step * (i + 1)})

        orbiting = _frames(url, args.frames, proc.pid, orbit)
        gens = [int(h["X-Generation"]) for h in orbiting["headers"]]
        # every orbit frame is the first image of a new view: its draft, its pass 1 or (beams)
        # the first band of its pass 1
        restarted = gens == list(range(gens[0], gens[0] + len(gens))) and all(
            (h["X-Draft"], h["X-Passes"]) in (("1", "0"), ("0", "1"), ("0", "0")) for h in orbiting["headers"]
        )
        cut = None
        if "object.0.pavilion_angle" in values:
            t0 = time.perf_counter()
            _post(
                url + "controls", {"object.0.pavilion_angle": float(values["object.0.pavilion_angle"]) + 0.5}
            )
            headers, _ = _get(url + "frame.jpg")
            cut = time.perf_counter() - t0
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    strip = lambda r: {k: v for k, v in r.items() if k != "headers"}  # noqa: E731
    return {
        "draft_scale": draft_scale,
        "command": " ".join(["warpoptics", "view", os.path.relpath(args.scene, ROOT), *cmd[5:]]),
        "startup_to_first_frame_s": t_first - t_launch,
        "server_ready_s": t_ready - t_launch,
        "first_frame_s": t_first - t_ready,
        "first_full_frame_s": t_full - t_ready,
        "first_whole_pass_s": t_pass - t_ready,
        "refining": strip(refining),
        "orbiting": strip(orbiting),
        "orbit_every_frame_restarted": restarted,
        "cut_change_s": cut,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "diamond.toml"))
    ap.add_argument("--width", type=int, default=400)
    ap.add_argument("--height", type=int, default=300)
    ap.add_argument("--frames", type=int, default=60, help="frames per phase (refining, orbiting)")
    ap.add_argument("--orbit-step", type=float, default=2.0, help="degrees of azimuth per orbit frame")
    ap.add_argument("--draft-scales", default="2,1", help="comma-separated --draft-scale values to measure")
    ap.add_argument("--quick", action="store_true", help="smoke run: 64x48, 4 frames per phase")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()
    if args.quick:
        args.width, args.height, args.frames = 64, 48, 4
    result = {
        "scene": os.path.relpath(args.scene, ROOT),
        "width": args.width,
        "height": args.height,
        "machine": {
            "cpus": len(os.sched_getaffinity(0)),
            "processor": platform.processor() or platform.machine(),
        },
        # the load average (1 min) before and after: wall times mean little on a busy machine
        "load_average_before": os.getloadavg()[0],
        "runs": [measure(args, int(s)) for s in args.draft_scales.split(",")],
    }
    result["load_average_after"] = os.getloadavg()[0]
    m, la = result["machine"], (result["load_average_before"], result["load_average_after"])
    print(f"warpoptics view {result['scene']} at {args.width}x{args.height} on {m['cpus']} CPUs")
    print(f"load average (1 min) {la[0]:.2f} before, {la[1]:.2f} after")
    ok = True
    for r in result["runs"]:
        print(f"draft scale {r['draft_scale']}: {r['command']}")
        print(
            f"  launch -> first frame        {r['startup_to_first_frame_s']:7.3f} s "
            f"(server up after {r['server_ready_s']:.3f} s)"
        )
        print(f"  server up -> first frame     {r['first_frame_s']:7.3f} s   (target < 0.5 s)")
        print(f"  server up -> first full-resolution frame {r['first_full_frame_s']:7.3f} s")
        print(f"  server up -> first whole full-resolution pass {r['first_whole_pass_s']:7.3f} s")
        for name in ("refining", "orbiting"):
            m = r[name]
            print(
                f"  {name:<10} {m['frames_per_s']:6.2f} frames/s, "
                f"median {m['median_frame_s'] * 1e3:6.1f} ms, slowest {m['max_frame_s'] * 1e3:6.1f} ms, "
                f"server CPU {m['server_cpu_s_per_frame'] * 1e3:6.1f} ms/frame"
            )
        print("  (target >= 5 frames/s while orbiting)")
        print(f"  every orbit frame restarted the accumulation: {r['orbit_every_frame_restarted']}")
        if r["cut_change_s"] is not None:
            print(f"  pavilion angle change -> its first frame {r['cut_change_s']:.3f} s")
        ok = ok and r["orbit_every_frame_restarted"]
    if args.json:
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
