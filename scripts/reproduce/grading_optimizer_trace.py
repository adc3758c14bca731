"""The cut optimizer's trace from a poor cut (warpoptics.sweep.optimize).

CMA-ES over pavilion (38-44°) and crown (25-40°) of a 6.5 mm round brilliant diamond (table
55 %), started at pavilion 43°, crown 30°, maximizing the protocol's light return plus half its
fire (``--objective``) under a total-depth constraint of 57-63 %, 40 evaluations.  Writes the
optimizer's folder (``trace.png``, ``parameters.png``, ``best.asc``, ``report.md``,
``journal.csv``); ``--resume`` continues a killed run from its journal.

    python scripts/reproduce/grading_optimizer_trace.py -o docs/gallery/optimizer [--dask-local 2]
    python scripts/reproduce/grading_optimizer_trace.py --quick -o /tmp/opt          # seconds
"""

from __future__ import annotations

import argparse
import dataclasses

from warpoptics.grading.performance import PROTOCOL
from warpoptics.sweep.optimize import Constraints, CutOptimizer, Parameter


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="docs/gallery/optimizer", help="output folder")
    ap.add_argument("--objective", default="light_return=1,fire=0.5")
    ap.add_argument("--budget", type=int, default=40)
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--dask-local", type=int, default=None)
    ap.add_argument("--quick", action="store_true", help="12 px, face-up only, 6 evaluations")
    args = ap.parse_args(argv)
    objective = {k: float(w) for k, _, w in (p.partition("=") for p in args.objective.split(","))}
    proto = dataclasses.replace(PROTOCOL, tilts=(0.0, 10.0), azimuths=(0.0,), size=48, wavelengths=8)
    budget = args.budget
    if args.quick:
        proto = dataclasses.replace(proto, tilts=(0.0,), size=12, wavelengths=2)
        budget = 6
    opt = CutOptimizer(
        {"shape": "round_brilliant", "diameter": 6.5, "table": 0.55, "material": "diamond"},
        [
            Parameter("pavilion", "object.0.pavilion_angle", 38.0, 44.0, 43.0),
            Parameter("crown", "object.0.crown_angle", 25.0, 40.0, 30.0),
        ],
        args.output,
        objective=objective,
        protocol=proto,
        constraints=Constraints(depth=(0.57, 0.63)),
        budget=budget,
        resume=args.resume,
        overwrite=not args.resume,
        dask_local=args.dask_local,
    )
    r = opt.run()
    b = r["best"]
    print(
        f"best: pavilion {b['values']['pavilion']:.2f}, crown {b['values']['crown']:.2f}: "
        f"J {b['objective']:.4f} "
        f"({r['evaluations']} evaluations, {r['infeasible']} infeasible, {r['renders']} renders)"
    )
    print(f"wrote {r['files']['trace']} and {r['files']['report']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
