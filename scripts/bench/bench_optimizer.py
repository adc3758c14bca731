"""Cut optimizer against a dense sweep: renders to reach the sweep's best (warpoptics.sweep.optimize).

Both in one run, on the same metric (the protocol's light return by default; ``--objective``),
the same protocol (face-up and tilted 10 deg, ISO light with a 10 deg head) and the same box
(pavilion 38-44 deg x crown 25-40 deg, table 55 %, diamond):

1. a dense product sweep of ``--grid`` x ``--grid`` cuts (441 at 21), through the sweep runner;
2. the CMA-ES optimizer started from a poor cut (pavilion 43 deg, crown 30 deg) with a budget of
   1/10 of the sweep's evaluations (whole generations within it).

Counts renders, not seconds.  The criterion: the optimizer's best is within 1 % of the sweep's
best (J_opt >= 0.99 J_sweep) and it spent at most 1/10 of the sweep's renders.  Also reported:
the renders the optimizer had spent when it first came within 1 %.  Writes (atomically)
``bench_optimizer.json`` and ``bench_optimizer.png`` (the sweep's map with the optimizer's
candidates) into ``--out``; the sweep and the optimizer folders are beside them and resume.

    python scripts/bench/bench_optimizer.py --out out/bench_optimizer            # the lead's run
    python scripts/bench/bench_optimizer.py --out out/bench_optimizer --dask-local 2
    python scripts/bench/bench_optimizer.py --quick --out /tmp/bench_opt           # seconds
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np

from warpoptics.atomic import atomic_path
from warpoptics.grading.performance import PROTOCOL
from warpoptics.sweep import Axis, SweepRunner
from warpoptics.sweep.grading import protocol_scores, protocol_sweep, renders_per_job
from warpoptics.sweep.optimize import OBJECTIVE_METRICS, CutOptimizer, Parameter
from warpoptics.sweep.results import write_text_atomic

STONE = {"shape": "round_brilliant", "diameter": 6.5, "table": 0.55, "material": "diamond"}
BOX = {
    "pavilion": ("object.0.pavilion_angle", 38.0, 44.0, 43.0),
    "crown": ("object.0.crown_angle", 25.0, 40.0, 30.0),
}


def _objective(text: str) -> dict[str, float]:
    out = {}
    for part in text.split(","):
        name, _, w = part.partition("=")
        name = name.strip()
        if name not in OBJECTIVE_METRICS:
            raise SystemExit(
                f"--objective: unknown metric {name!r} (allowed: {', '.join(OBJECTIVE_METRICS)})"
            )
        out[name] = float(w) if w else 1.0
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="bench_optimizer")
    ap.add_argument("--grid", type=int, default=21, help="sweep points per parameter (default 21)")
    ap.add_argument("--size", type=int, default=40, help="image size, pixels (default 40)")
    ap.add_argument("--wavelengths", type=int, default=4)
    ap.add_argument("--objective", default="light_return", help="metric=weight,... (default light_return)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--dask-local", type=int, default=None, help="run both on a local Dask cluster of N")
    ap.add_argument("--quick", action="store_true", help="3 x 3 grid, 16 px, face-up only: seconds")
    args = ap.parse_args(argv)
    objective = _objective(args.objective)
    fire = any(objective.get(m, 0) for m in ("fire", "scintillation"))
    proto = dataclasses.replace(
        PROTOCOL, tilts=(0.0, 10.0), azimuths=(0.0,), size=args.size, wavelengths=args.wavelengths
    )
    grid = args.grid
    if args.quick:
        proto = dataclasses.replace(proto, tilts=(0.0,), size=16, wavelengths=2)
        grid = 3
    out = Path(args.out)
    runner_kw = {"dask_local": args.dask_local, "progress": False}

    # 1. the dense sweep
    axes = [
        Axis(name, tuple(float(v) for v in np.round(np.linspace(lo, hi, grid), 6)), path=path)
        for name, (path, lo, hi, _s) in BOX.items()
    ]
    sweep = protocol_sweep(STONE, proto, axes=axes, mode="product", fire=fire, name="dense")
    res = SweepRunner(sweep, out / "dense", resume=True, **runner_kw).run()
    per = renders_per_job(sweep)

    def score(row):
        m = protocol_scores(row, proto, fire=fire)
        return float(sum(w * m[k] for k, w in objective.items()))

    dense = [(float(r["pavilion"]), float(r["crown"]), score(r)) for r in res.rows]
    best_sweep = max(dense, key=lambda t: t[2])
    sweep_renders = len(dense) * per

    # 2. the optimizer, 1/10 of the sweep's evaluations
    params = [Parameter(name, path, lo, hi, start) for name, (path, lo, hi, start) in BOX.items()]
    popsize = 4 + int(3 * np.log(len(params)))
    budget = max(popsize, len(dense) // 10)
    opt = CutOptimizer(
        STONE,
        params,
        out / "optimizer",
        objective=objective,
        protocol=proto,
        budget=budget,
        seed=args.seed,
        resume=True,
        **runner_kw,
    )
    r = opt.run()
    target = 0.99 * best_sweep[2]
    reached = next((i + 1 for i, (_k, j) in enumerate(r["trace"]) if j >= target), None)
    summary = {
        "objective": objective,
        "protocol": dataclasses.asdict(proto),
        "grid": grid,
        "sweep": {"evaluations": len(dense), "renders": sweep_renders, "best": best_sweep},
        "optimizer": {
            "evaluations": r["evaluations"],
            "renders": r["renders"],
            "best": [r["best"]["values"]["pavilion"], r["best"]["values"]["crown"], r["best"]["objective"]],
            "evaluations_to_within_1pct": reached,
            "renders_to_within_1pct": None if reached is None else reached * per,
        },
        "ratio_best": r["best"]["objective"] / best_sweep[2],
        "ratio_renders": r["renders"] / sweep_renders,
    }
    summary["pass"] = bool(summary["ratio_best"] >= 0.99 and summary["ratio_renders"] <= 0.1)
    write_text_atomic(out / "bench_optimizer.json", json.dumps(summary, indent=1) + "\n")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pav = sorted({d[0] for d in dense})
    cro = sorted({d[1] for d in dense})
    z = np.full((len(cro), len(pav)), np.nan)
    for p, c, j in dense:
        z[cro.index(c), pav.index(p)] = j
    fig, ax = plt.subplots(figsize=(5.6, 4.4))
    im = ax.pcolormesh(pav, cro, z, shading="nearest", cmap="viridis")
    fig.colorbar(im, label="objective J (dense sweep)")
    hist = [(float(x["pavilion"]), float(x["crown"])) for x in _journal(out / "optimizer" / "journal.csv")]
    ax.plot([h[0] for h in hist], [h[1] for h in hist], ".-", color="w", lw=0.6, ms=4, label="optimizer")
    ax.plot([BOX["pavilion"][3]], [BOX["crown"][3]], "s", color="C1", label="start")
    ax.plot([best_sweep[0]], [best_sweep[1]], "*", ms=12, color="C3", label="sweep best")
    ax.set_xlabel("pavilion angle (°)")
    ax.set_ylabel("crown angle (°)")
    ax.set_title(
        f"{len(dense)} sweep renders x{per} vs {r['evaluations']} optimizer evaluations: "
        f"J {summary['ratio_best']:.4f} of the sweep's best",
        fontsize=8,
    )
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    with atomic_path(out / "bench_optimizer.png") as tmp:
        fig.savefig(tmp, dpi=110)
    print(json.dumps(summary, indent=1))
    return 0


def _journal(path: Path) -> list[dict]:
    from warpoptics.sweep.results import read_results

    _h, rows = read_results(path)
    return rows


if __name__ == "__main__":
    raise SystemExit(main())
