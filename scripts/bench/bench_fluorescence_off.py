"""Cost of the re-emission code with fluorescence off: this checkout against a baseline checkout.

The re-emission estimator of ``stages/fluorescence.py`` is compiled only into the fluorescent
variant of the camera trace (``stages/trace.py``, ``wp.static``); a scene without a fluorescent
medium runs the tracer without it.  This benchmark renders the same non-fluorescent scenes with
this checkout and with a baseline checkout (``--baseline``: any tree of warpoptics without the
change, e.g. ``git worktree add ../before <commit>``) in alternating child processes (A B B A ...), one
render thread each, and reports the CPU seconds of the render itself (kernels loaded before the
clock starts) and the ratio candidate / baseline per scene, with the images compared for
equality.  The default scenes use one path tree per wavelength, where the code lives: the
sapphire (a uniaxial stone) and the diamond with ``render.bundle = false``.

    python scripts/bench/bench_fluorescence_off.py --baseline ../before [--size 48] [--rounds 3]
    python scripts/bench/bench_fluorescence_off.py --baseline ../before --size 16 --rounds 1  # smoke
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = {
    "sapphire": ("scenes/sapphire.toml", {}),
    "diamond_trees": ("scenes/diamond.toml", {"bundle": False}),
}


def _child(scene: str, size: int, out: str | None) -> None:
    import hashlib

    import numpy as np

    from warpoptics.pipelines.render import Renderer
    from warpoptics.scene import Scene

    file, over = SCENES[scene]
    sc = Scene.load(ROOT / file).with_overrides(width=size, height=size, **over)
    r = Renderer(sc)
    r.load_kernels()
    t0 = time.process_time()
    img = r.run(threads=1)
    cpu = time.process_time() - t0
    xyz = np.ascontiguousarray(img.xyz)
    print(
        json.dumps(
            {
                "cpu_s": cpu,
                "rays": img.stats["rays"],
                "xyz_sha1": hashlib.sha1(xyz.tobytes()).hexdigest(),
                "module": str(Path(sys.modules["warpoptics"].__file__).parent),
            }
        )
    )


def _run(tree: Path, scene: str, size: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", scene, "--size", str(size)]
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, cwd=tree)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, help="a warpoptics checkout without the change")
    ap.add_argument("--size", type=int, default=48, help="image width and height")
    ap.add_argument("--rounds", type=int, default=3, help="A B B A rounds per scene")
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--json", default=None, help="write the results here")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args.child, args.size, None)
        return 0
    trees = {"baseline": Path(args.baseline).resolve(), "candidate": ROOT}
    out: dict = {
        "size": args.size,
        "rounds": args.rounds,
        "note": "CPU seconds, one render thread",
        "scenes": {},
    }
    for scene in args.scenes:
        runs: dict[str, list[dict]] = {"baseline": [], "candidate": []}
        for name in trees:  # warm-up (compiles each tree's kernels into the cache), not timed
            _run(trees[name], scene, 8)
        for k in range(args.rounds):
            order = ("baseline", "candidate") if k % 2 == 0 else ("candidate", "baseline")
            for name in order + order[::-1]:
                runs[name].append(_run(trees[name], scene, args.size))
        cpu = {n: statistics.median(r["cpu_s"] for r in runs[n]) for n in runs}
        same = {r["xyz_sha1"] for r in runs["baseline"] + runs["candidate"]}
        out["scenes"][scene] = {
            "baseline_cpu_s": cpu["baseline"],
            "candidate_cpu_s": cpu["candidate"],
            "ratio": cpu["candidate"] / cpu["baseline"],
            "all_cpu_s": {n: [r["cpu_s"] for r in runs[n]] for n in runs},
            "rays": runs["candidate"][0]["rays"],
            "images_identical": len(same) == 1,
        }
        s = out["scenes"][scene]
        print(
            f"{scene}: baseline {s['baseline_cpu_s']:.3f} CPU-s, candidate {s['candidate_cpu_s']:.3f} CPU-s, "
            f"ratio {s['ratio']:.3f} (median of {2 * args.rounds}), images identical: {s['images_identical']}"
        )
    if args.json:
        from warpoptics.sweep.results import write_text_atomic

        write_text_atomic(Path(args.json), json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
