"""Fire convergence: relative RMSE against a long reference vs cost, per spectral estimator.

Scene: the fire benchmark stone -- ``scenes/bench_diamond.toml`` (Tolkowsky brilliant, the
studio map as a lat-long EXR, 16 scattering events, split threshold 0.05) with the library's
dispersive ``diamond`` (``absorption_scale = 0``), polarized; uniform sampling (no adaptive
pass) so that the estimators' rates show.  Estimators:

- ``separate``: one path tree per wavelength sample, each at its own pixel position (the
  renderer before the spectral bundle; ``render.bundle = false``);
- ``bundle``: one tree for a bundle of ``--lanes`` wavelengths at one pixel position
  (``stages/bundle.py``, the default for such scenes);
- ``clear``: the same stone without dispersion (n = 2.4173, one tree for the whole spectrum) --
  the speed the issue asks the dispersive stone to come within 3x of.

Error: relative RMSE of linear sRGB over the whole image, sqrt(mean((a - r)^2)) / mean(r), against
the estimator family's long reference r (the bundle's for the dispersive estimators -- all are
unbiased, ``tests/test_bundle.py`` -- the clear stone's own for ``clear``).  The reference is
rendered as two halves with independent seeds: their difference measures its noise, which is
subtracted in quadrature (err^2 = rmse(a, r)^2 - rmse(h1, h2)^2 / 4).  Cost: rays traced (ray
queries) and single-threaded CPU seconds (``time.process_time``, ``threads=1``), never wall
clock, so that a loaded machine does not bias the comparison.  For each estimator a ladder of
sample counts is rendered (independent seeds), and the CPU seconds to reach ``--target`` are read
from a power-law fit of error vs CPU seconds over the ladder (interpolated when the ladder spans
the target, else extrapolated and marked so).

    python scripts/bench/fire_convergence.py --quick            # seconds (16x16), a smoke run
    python scripts/bench/fire_convergence.py                    # 64x64, about 20 CPU-minutes
    python scripts/bench/fire_convergence.py --res 128 --ref-spp 4096 --json out.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import warpoptics as wo  # noqa: E402
from warpoptics.pipelines.render import Renderer  # noqa: E402

CLEAR = {"cauchy": [2.4173]}


def scene_for(estimator: str, res: int, wavelengths: int, lanes: int):
    sc = wo.Scene.load(ROOT / "scenes" / "bench_diamond.toml")
    material = CLEAR if estimator == "clear" else "diamond"
    return sc.with_overrides(
        {"object.0.material": material, "object.0.absorption_scale": 0.0},
        width=res,
        height=res,
        adaptive=False,
        polarization=True,
        wavelengths=wavelengths,
        bundle=estimator != "separate",
        bundle_lanes=lanes,
    )


def render(sc, spp: int, seed: int) -> tuple[np.ndarray, float, int]:
    """(linear sRGB, CPU seconds of the render on one thread, rays traced)."""
    r = Renderer(sc.with_overrides(None, spp=spp, seed=seed))
    t0 = time.process_time()
    img = r.run(threads=1)
    return img.rgb.astype(np.float64), time.process_time() - t0, int(img.stats["rays"])


def rel_rmse(a: np.ndarray, b: np.ndarray, mean: float) -> float:
    return float(np.sqrt(((a - b) ** 2).mean()) / mean)


def reference(sc, spp: int, log) -> dict:
    h1, c1, _ = render(sc, spp, seed=900001)
    h2, c2, _ = render(sc, spp, seed=900002)
    ref = 0.5 * (h1 + h2)
    mean = float(ref.mean())
    noise = 0.5 * rel_rmse(h1, h2, mean)  # rmse(ref, truth) = rmse(h1, h2) / 2
    log(f"  reference: 2 x {spp} spp, {c1 + c2:.1f} CPU-s, its own noise {100 * noise:.3f} %")
    return {"image": ref, "mean": mean, "noise": noise, "cpu_seconds": c1 + c2, "spp": 2 * spp}


def seconds_to(target: float, cpu: np.ndarray, err: np.ndarray) -> tuple[float, float, bool]:
    """(CPU seconds at ``target`` from a power-law fit err = a cpu^-b, slope b, interpolated?)."""
    ok = err > 0
    slope, icpt = np.polyfit(np.log(cpu[ok]), np.log(err[ok]), 1)
    t = float(np.exp((np.log(target) - icpt) / slope))
    return t, float(-slope), bool(err[ok].min() <= target <= err[ok].max())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--wavelengths", type=int, default=8, help="wavelength samples per spp")
    ap.add_argument("--lanes", type=int, default=8, help="wavelengths per bundle")
    ap.add_argument("--ladder", type=int, nargs="+", default=[8, 32, 128], help="spp of the passes")
    ap.add_argument("--ref-spp", type=int, default=2048, help="spp of each reference half")
    ap.add_argument("--target", type=float, default=0.01)
    ap.add_argument("--estimators", nargs="+", default=["separate", "bundle", "clear"])
    ap.add_argument("--json", type=Path)
    ap.add_argument("--quick", action="store_true", help="16x16, a short ladder (seconds)")
    args = ap.parse_args(argv)
    if args.quick:
        args.res, args.ladder, args.ref_spp, args.target = 16, [2, 8], 32, 0.1

    def log(msg):
        print(msg, flush=True)

    log(
        f"fire convergence: {args.res}x{args.res}, {args.wavelengths} wavelengths per spp, "
        f"bundles of {args.lanes}, polarized, ladder {args.ladder} spp, target {100 * args.target:g} %"
    )
    for est in args.estimators:  # compile every kernel variant before anything is timed
        render(scene_for(est, 8, args.wavelengths, args.lanes), 1, 0)
    refs: dict[str, dict] = {}
    rows = []
    for est in args.estimators:
        fam = "clear" if est == "clear" else "dispersive"
        if fam not in refs:
            log(f"{fam}:")
            refs[fam] = reference(
                scene_for("clear" if fam == "clear" else "bundle", args.res, args.wavelengths, args.lanes),
                args.ref_spp,
                log,
            )
        ref = refs[fam]
        sc = scene_for(est, args.res, args.wavelengths, args.lanes)
        for i, spp in enumerate(args.ladder):
            img, cpu, rays = render(sc, spp, seed=1000 * (i + 1) + 7)
            raw = rel_rmse(img, ref["image"], ref["mean"])
            err = float(np.sqrt(max(raw**2 - ref["noise"] ** 2, 0.0)))
            rows.append(
                {"estimator": est, "spp": spp, "cpu_seconds": cpu, "rays": rays, "rel_rmse": err, "raw": raw}
            )
            log(
                f"  {est:9s} {spp:6d} spp  {cpu:8.2f} CPU-s  {rays / 1e6:9.2f} M rays"
                f"  rel. RMSE {100 * err:7.3f} %"
            )
    log("")
    log(f"| estimator | slope (err ~ CPU-s^-b) | CPU-s to {100 * args.target:g} % | x clear |")
    log("|---|---|---|---|")
    summary = {}
    for est in args.estimators:
        r = [x for x in rows if x["estimator"] == est]
        t, b, inside = seconds_to(
            args.target, np.array([x["cpu_seconds"] for x in r]), np.array([x["rel_rmse"] for x in r])
        )
        summary[est] = {"cpu_seconds_to_target": t, "slope": b, "interpolated": inside}
    for est, s in summary.items():
        ratio = (
            s["cpu_seconds_to_target"] / summary["clear"]["cpu_seconds_to_target"]
            if "clear" in summary
            else float("nan")
        )
        mark = "" if s["interpolated"] else " (extrapolated)"
        log(f"| {est} | {s['slope']:.2f} | {s['cpu_seconds_to_target']:.2f}{mark} | {ratio:.1f} |")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        out = {
            "args": {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()},
            "rows": rows,
            "summary": summary,
            "references": {k: {kk: vv for kk, vv in v.items() if kk != "image"} for k, v in refs.items()},
        }
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
