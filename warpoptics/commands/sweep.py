"""`warpoptics sweep SWEEP.toml -o DIR`: run a parameter sweep (results.csv, images, plots, summary.md)."""

from __future__ import annotations

import sys


def run(args) -> int:
    from ..scene.load import parse_set_options
    from ..sweep import Sweep, SweepRunner

    extra = parse_set_options(args.set)
    sweep = Sweep.load(args.sweep, extra_set=extra)
    jobs = sweep.jobs()
    if args.list:
        for j in jobs:
            print(f"{j.key}  {j.label}")
        return 0
    runner = SweepRunner(
        sweep,
        args.output,
        workers=args.workers,
        executor=args.executor,
        scheduler=args.scheduler,
        dask_local=args.dask_local,
        resume=args.resume,
        overwrite=args.overwrite,
        progress=not args.quiet,
        device=args.device,
    )
    result = runner.run()
    print(f"{args.output}: {len(result.rows)}/{len(result.jobs)} jobs done ({result.rendered} rendered now)")
    if "summary" in result.files:
        print(f"summary: {result.files['summary']}")
    if result.pairs:
        first = result.pairs[0]
        others = [
            k
            for k in first
            if k not in ("index", "key", "reference_key", "label", "diff_image") and not k.startswith("dE")
        ]
        print("paired CIEDE2000 (" + ", ".join(others) + "): mean / p95 / of mean colours")
        for p in result.pairs:
            print(
                "  "
                + ", ".join(str(p[k]) for k in others)
                + f": {p['dE_mean']:.3f} / {p['dE_p95']:.3f} / {p['dE_mean_color']:.3f}"
            )
    sys.stdout.flush()
    if not result.complete:
        # rows are missing (a worker died twice on a job): say which and why, and exit non-zero
        print(f"warpoptics sweep: incomplete: {result.report()}", file=sys.stderr)
        return 1
    return 0


def register(sub) -> None:
    p = sub.add_parser("sweep", help="run a parameter sweep (TOML) into a folder: results.csv, images, plots")
    p.add_argument("sweep", help="sweep definition (.toml)")
    p.add_argument("-o", "--output", required=True, help="output folder")
    p.add_argument("--resume", action="store_true", help="continue a sweep in a folder that has results")
    p.add_argument("--overwrite", action="store_true", help="start again in a folder that has results")
    p.add_argument(
        "--workers",
        type=int,
        default=1,
        help="jobs at once on this machine (default 1: one job at a time on every core)",
    )
    p.add_argument(
        "--executor",
        choices=("process", "thread"),
        default="process",
        help="pool kind for --workers > 1 (default process)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument("--scheduler", metavar="ADDR", help="run the jobs on a Dask cluster (tcp://HOST:PORT)")
    g.add_argument(
        "--dask-local", type=int, metavar="N", help="run the jobs on a local Dask cluster of N workers"
    )
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override a scene value in every job, e.g. --set camera.width=64",
    )
    p.add_argument("--list", action="store_true", help="print the jobs and exit")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)
