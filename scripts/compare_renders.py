"""Render every scene the gallery is made from with two checkouts and compare the images.

A refactor of the transport must not change what the renderer computes.  This script renders, with
the code of ONE checkout (``--root``, default this one), every camera scene under ``scenes/`` and
every optical-bench scene under ``scenes/bench/`` at a small size, each twice with two seeds, into
``--out`` as EXR files (``render``) and ``compare`` then holds two such folders against each other:

- **byte-identical** EXR pixels: the estimator did not change at all;
- otherwise **within noise**: the per-image root-mean-square difference of the two checkouts
  (same seed) is compared with the RMS difference between the two seeds of the *reference*
  checkout, i.e. with the Monte Carlo noise of one render.  A change that only moves round-off
  (a formula computed in another order, a random normal drawn in another frame) gives a ratio far
  below 1 wherever the splits are deterministic, and at most ~1 where random choices diverge; a
  real change of the physics gives ratios >> 1.  The bound asserted is ratio <= 1.5 (two
  independent renders of the same estimator differ by sqrt(2) x the noise of one).

Usage (before/after a change; the first command in a worktree of the old commit)::

    python scripts/compare_renders.py render --root /path/to/old/checkout --out /tmp/before
    python scripts/compare_renders.py render --out /tmp/after
    python scripts/compare_renders.py compare /tmp/before /tmp/after
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
SIZE = 40  # pixels (camera scenes), small enough for the whole set in a few minutes on 2 cores
BOUND = 1.5


def _jobs(root: Path) -> list[tuple[str, list[str]]]:
    jobs = []
    for scene in sorted((root / "scenes").glob("*.toml")):
        for seed in (0, 1):
            args = [
                "render",
                str(scene),
                "--width",
                str(SIZE),
                "--height",
                str(SIZE),
                "--spp",
                "2",
                "--set",
                "render.adaptive=false",
                "--set",
                f"render.seed={seed}",
            ]
            jobs.append((f"{scene.stem}.seed{seed}", args))
    for scene in sorted((root / "scenes" / "bench").glob("*.toml")):
        for seed in (0, 1):
            jobs.append(
                (
                    f"bench_{scene.stem}.seed{seed}",
                    ["bench", str(scene), "--rays", "400", "--set", f"render.seed={seed}"],
                )
            )
    return jobs


def render(root: Path, out: Path, only: str | None = None) -> int:
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=str(root))
    failed = 0
    for name, args in _jobs(root):
        if only and only not in name:
            continue
        target = out / f"{name}.exr"
        cmd = [sys.executable, "-m", "warpoptics.cli", *args, "-o", str(target)]
        res = subprocess.run(cmd, cwd=root, env=env, capture_output=True, text=True, check=False)
        status = "ok" if res.returncode == 0 else f"FAILED ({res.returncode})"
        print(f"{name:40s} {status}", flush=True)
        if res.returncode != 0:
            failed += 1
            print(res.stderr[-2000:], file=sys.stderr)
    return 1 if failed else 0


def _read(path: Path) -> np.ndarray:
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise SystemExit(f"cannot read {path}")
    data = inp.read_image(format="float")
    inp.close()
    return np.asarray(data, dtype=np.float64)


def compare(before: Path, after: Path) -> int:
    rows, worst = [], 0.0
    for b0 in sorted(before.glob("*.seed0.exr")):
        stem = b0.name[: -len(".seed0.exr")]
        a0 = after / b0.name
        b1 = before / f"{stem}.seed1.exr"
        if not a0.exists():
            rows.append({"image": stem, "verdict": "MISSING"})
            worst = float("inf")
            continue
        x, y, z = _read(b0), _read(a0), _read(b1)
        if x.shape != y.shape:
            rows.append({"image": stem, "verdict": f"SHAPE {x.shape} vs {y.shape}"})
            worst = float("inf")
            continue
        identical = bool(np.array_equal(x, y))
        diff = float(np.sqrt(np.mean((x - y) ** 2)))
        noise = float(np.sqrt(np.mean((x - z) ** 2)))
        ratio = 0.0 if identical else (diff / noise if noise > 0 else (0.0 if diff == 0 else float("inf")))
        worst = max(worst, ratio)
        verdict = "byte-identical" if identical else ("within noise" if ratio <= BOUND else "DIFFERENT")
        rows.append(
            {
                "image": stem,
                "verdict": verdict,
                "rms_diff": diff,
                "rms_seed_noise": noise,
                "ratio": ratio,
                "max_abs_diff": float(np.max(np.abs(x - y))),
            }
        )
    for r in rows:
        extra = (
            ""
            if "ratio" not in r
            else (
                f"  rms diff {r['rms_diff']:.3e}  seed noise {r['rms_seed_noise']:.3e}"
                f"  ratio {r['ratio']:.3f}"
                f"  max |diff| {r['max_abs_diff']:.3e}"
            )
        )
        print(f"{r['image']:32s} {r['verdict']:15s}{extra}")
    from warpoptics.atomic import atomic_path

    with atomic_path(after / "comparison.json") as tmp:
        Path(tmp).write_text(json.dumps(rows, indent=1))
    n_id = sum(r["verdict"] == "byte-identical" for r in rows)
    print(f"{n_id} of {len(rows)} byte-identical; worst noise ratio {worst:.3f} (bound {BOUND})")
    return 0 if worst <= BOUND else 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("render")
    r.add_argument("--root", default=str(HERE), help="checkout whose code renders (default: this one)")
    r.add_argument("--out", required=True)
    r.add_argument("--only", default=None, help="render only the jobs whose name contains this")
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    a = ap.parse_args(argv)
    if a.cmd == "render":
        return render(Path(a.root).resolve(), Path(a.out), a.only)
    return compare(Path(a.before), Path(a.after))


if __name__ == "__main__":
    raise SystemExit(main())
