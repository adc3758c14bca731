"""warpoptics against Mitsuba 3 at equal error on the non-dispersive diamond.

Scene: ``scenes/bench_diamond.toml`` (Tolkowsky round brilliant, n = 2.4173, studio light as a
lat-long EXR read by both renderers, 256x256, 16 scattering events: our max_depth 16, Mitsuba's
max_depth 17), unpolarized.  Mitsuba gets the scene through ``warpoptics.mitsuba_export``.

Method.  Each renderer renders independent passes (different seeds; ours ``spp`` x
``wavelengths`` pixel samples per pixel on average, Mitsuba ``--mitsuba-spp`` paths per pixel)
for a time budget, after one untimed warm-up pass (kernel compilation); the passes of the
renderers alternate, so that all see the same load on a shared machine.  Image quantity:
luminance Y.  For unbiased, independent passes the relative RMSE of the mean of k passes against
the renderer's own converged image is sigma_1 / sqrt(k), sigma_1 = sqrt(mean over pixels of the
per-pixel variance of one pass) / mean Y, so the time to reach ``--target`` (1 %) is
``t_pass * (sigma_1 / target)**2`` when that is one pass or more; when one pass is already below
the target, it is the time of one pass (never extrapolated below a pass).  Pass sizes matter for
low-discrepancy and adaptive samplers (our R2 pixel positions and adaptive sampling; Mitsuba's
``ldsampler``): a pass of N samples has sigma_1 falling faster than 1/sqrt(N), so each renderer
gets the pass size that minimises its time — ours one pass at about the target (``--spp``, the
scene's ``adaptive = true``: a pilot, then the samples where the noise is, warpoptics/adaptive.py),
Mitsuba ``ldsampler`` 32-64 spp (larger passes measured slower to target).  ``--uniform-seconds``
also runs ours with the same spp in every pixel, to show what the adaptive sampling adds.  The
1/sqrt(k) law is checked on the measured passes: the RMSE between the means of two disjoint
halves of the passes must be sqrt(2) sigma_1 / sqrt(k/2).  When a renderer's passes reach the
target themselves the time is also read off directly.

Agreement of the converged images: with the passes split into two independent halves (a1, a2
ours; b1, b2 Mitsuba), mean((a1 - b1) (a2 - b2)) is an unbiased estimate of the mean squared
difference of the two converged images (the noise cancels); its square root over Mitsuba's mean
is the "converged relative RMSE" (target < 2 %), reported with a one-sided 2-sigma upper bound.
The raw relative RMSE between the two pass means (noise included) is reported as well.

    python scripts/bench/bench_mitsuba.py                 # the full measurement (about 40 min)
    python scripts/bench/bench_mitsuba.py --json scripts/bench/results/bench_mitsuba_256.json
    python scripts/bench/bench_mitsuba.py --quick         # a smoke run (64x64, seconds)
    python scripts/bench/bench_mitsuba.py --ours-seconds 1200 --mitsuba-seconds 900 --json out.json

Mitsuba's ``llvm_ad_spectral`` variant needs ``DRJIT_LIBLLVM_PATH`` (Debian: libllvm19,
/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1; set here when present); without LLVM the script
falls back to ``scalar_spectral`` and says so.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(LLVM):
    os.environ["DRJIT_LIBLLVM_PATH"] = LLVM
sys.path.insert(0, str(Path(__file__).resolve().parent))
from equal_error import (  # noqa: E402  (the machinery shared with bench_fire.py)
    OursRunner,
    converged_difference,
    run_interleaved,
    shown,
    time_to_target,
)


class MitsubaRunner:
    def __init__(
        self, scene, variant: str, spp: int, log, env_step: float = 1.0, sampler: str = "independent"
    ):
        import mitsuba as mi

        from warpoptics.pipelines import mitsuba_export as mx

        mi.set_variant(variant)
        self.mx, self.scene, self.spp, self.ims, self.times = mx, scene, spp, [], []
        self.name = "mitsuba"
        t0 = time.perf_counter()
        self.loaded = mx.load_mitsuba_scene(scene, env_step=env_step, sampler=sampler)
        log(f"mitsuba: scene export (envmap bake) + load {time.perf_counter() - t0:.1f} s")
        t0 = time.perf_counter()
        mx.render_mitsuba(scene, spp=spp, seed=10_000, mi_scene=self.loaded)  # warm-up: JIT compilation
        log(f"mitsuba: warm-up pass {time.perf_counter() - t0:.1f} s")

    def step(self):
        r = self.mx.render_mitsuba(self.scene, spp=self.spp, seed=len(self.ims), mi_scene=self.loaded)
        self.times.append(r["seconds"])
        self.ims.append(r["y"])


def pick_variant(requested: str | None, log) -> str:
    import mitsuba as mi

    for v in [requested] if requested else ["llvm_ad_spectral", "scalar_spectral"]:
        try:
            mi.set_variant(v)
            if v.startswith("llvm"):
                import drjit as dr

                _ = dr.llvm.Float([1.0, 2.0]) + 1.0  # fails without a usable libLLVM
            return v
        except Exception as exc:  # noqa: BLE001 - report and fall back
            log(f"mitsuba variant {v} unavailable ({exc}); falling back")
    raise SystemExit("no usable Mitsuba variant")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "bench_diamond.toml"))
    ap.add_argument("--quick", action="store_true", help="smoke run: 64x64, a few passes")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--target", type=float, default=0.01, help="relative RMSE (default 1 %%)")
    ap.add_argument(
        "--wavelengths", type=int, help="our stratified wavelengths per spp (default: the scene's)"
    )
    ap.add_argument(
        "--spp",
        type=int,
        default=32,
        help="our spp per pass (x the scene's 8 wavelengths, adaptive: about 0.9 %% noise per pass)",
    )
    ap.add_argument("--ours-seconds", type=float, default=900.0, help="time budget of our passes")
    ap.add_argument(
        "--uniform-seconds",
        type=float,
        default=0.0,
        help="also run ours without adaptive sampling for this budget (0: not)",
    )
    ap.add_argument("--mitsuba-seconds", type=float, default=900.0, help="time budget of Mitsuba's passes")
    ap.add_argument("--mitsuba-spp", type=int, default=64, help="Mitsuba spp per pass")
    ap.add_argument(
        "--mitsuba-sampler",
        default="ldsampler",
        help="Mitsuba sampler (ldsampler: its fastest to 1 %% here; independent, multijitter, ...)",
    )
    ap.add_argument("--min-passes", type=int, default=4)
    ap.add_argument("--max-passes", type=int, default=100_000)
    ap.add_argument("--variant", help="Mitsuba variant (default llvm_ad_spectral, else scalar_spectral)")
    ap.add_argument(
        "--env-step",
        type=float,
        default=1.0,
        help="wavelength step (nm) of the envmap bake for Mitsuba (quick: 10)",
    )
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--save", help="write the mean images (ours, Mitsuba) to this .npz")
    args = ap.parse_args(argv)

    from equal_error import log

    import warpoptics as wo

    scene = wo.Scene.load(args.scene)
    over = {}
    m = scene.lights[0].map
    if m not in ("studio", "dome", "sky", "constant") and not Path(m).is_absolute():
        # the scene's map path is relative to the repository root
        over["light.0.map"] = str(ROOT / m)
    if args.quick:
        over.update({"camera.width": 64, "camera.height": 64})
        args.ours_seconds = min(args.ours_seconds, 5.0)
        args.mitsuba_seconds = min(args.mitsuba_seconds, 5.0)
        args.mitsuba_spp = min(args.mitsuba_spp, 16)
        args.spp = min(args.spp, 4)  # adaptive: a pilot of 2, then 2 more on average
        args.env_step = max(args.env_step, 10.0)
    for key, val in (
        ("camera.width", args.width),
        ("camera.height", args.height),
        ("render.wavelengths", args.wavelengths),
        ("render.spp", args.spp),
    ):
        if val is not None:
            over[key] = val
    scene = scene.with_overrides(over)
    r = scene.render
    if r.polarization:
        scene = scene.with_overrides({"render.polarization": False})
    w, h = scene.camera.width, scene.camera.height
    per_pass = r.spp * (r.wavelengths if r.spectral == "stratified" else 1)
    log(
        f"scene {shown(args.scene)}: {w}x{h}, ours {r.spectral} {r.wavelengths} wavelengths x spp {r.spp}, "
        f"max_depth {r.max_depth} (Mitsuba {r.max_depth + 1}); cpu cores {os.cpu_count()}"
    )
    variant = pick_variant(args.variant, log)
    log(
        f"mitsuba {__import__('mitsuba').__version__} variant {variant}, sampler {args.mitsuba_sampler}, "
        f"{args.mitsuba_spp} spp per pass"
    )

    mr = MitsubaRunner(
        scene, variant, args.mitsuba_spp, log, env_step=args.env_step, sampler=args.mitsuba_sampler
    )
    orun = OursRunner(scene, log, name="ours" + (" adaptive" if r.adaptive else ""))
    runners, budgets = [orun, mr], [args.ours_seconds, args.mitsuba_seconds]
    urun = None
    if args.uniform_seconds > 0 and r.adaptive:
        # the same renderer with every pixel at the same spp: what the adaptive sampling adds
        urun = OursRunner(scene.with_overrides({"render.adaptive": False}), log, name="ours uniform")
        runners.append(urun)
        budgets.append(args.uniform_seconds)
    run_interleaved(runners, budgets, args.min_passes, args.max_passes, log)
    ours, t_ours = np.array(orun.ims), orun.times
    theirs, t_theirs = np.array(mr.ims), mr.times

    res = {
        "scene": shown(args.scene),
        "width": w,
        "height": h,
        "target": args.target,
        "mitsuba_variant": variant,
        "mitsuba_sampler": args.mitsuba_sampler,
        "ours_adaptive": bool(r.adaptive),
        "ours": time_to_target(ours, t_ours, per_pass, args.target),
        "mitsuba": time_to_target(theirs, t_theirs, args.mitsuba_spp, args.target),
        "agreement": converged_difference(ours, theirs),
    }
    res["speedup_at_target"] = res["mitsuba"]["seconds_to_target"] / res["ours"]["seconds_to_target"]
    cols = [(orun.name, res["ours"])]
    if urun is not None:
        res["ours_uniform"] = time_to_target(np.array(urun.ims), urun.times, per_pass, args.target)
        res["ours_uniform"]["speedup_at_target"] = (
            res["mitsuba"]["seconds_to_target"] / res["ours_uniform"]["seconds_to_target"]
        )
        res["agreement_uniform"] = converged_difference(np.array(urun.ims), theirs)
        cols.append((urun.name, res["ours_uniform"]))
    cols.append((f"Mitsuba {variant}", res["mitsuba"]))
    a = res["agreement"]
    print()

    def row(label, fmt):
        print(f"| {label} | " + " | ".join(fmt(c) for _, c in cols) + " |")

    print(f"| {w}x{h}, to {100 * args.target:g} % rel. RMSE of Y | " + " | ".join(n for n, _ in cols) + " |")
    print("|---" * (len(cols) + 1) + "|")
    row("samples per pixel per pass (mean)", lambda c: f"{c['samples_per_pass']}")
    row("passes", lambda c: f"{c['passes']}")
    row("seconds per pass (median)", lambda c: f"{c['seconds_per_pass']:.3f}")
    row("rel. RMSE of one pass", lambda c: f"{c['rel_noise_one_pass']:.4f}")
    row(
        "half-split check measured / predicted",
        lambda c: f"{c['half_split_rel_rmse_measured']:.4f} / {c['half_split_rel_rmse_predicted']:.4f}",
    )
    row("samples per pixel to target", lambda c: f"{c['samples_to_target']:.0f}")
    row(
        "**seconds to target**",
        lambda c: (
            f"**{c['seconds_to_target']:.1f}**" + (" (one pass)" if c["one_pass_reaches_target"] else "")
        ),
    )
    row(
        "speed-up (Mitsuba time / this)",
        lambda c: f"{res['mitsuba']['seconds_to_target'] / c['seconds_to_target']:.2f}",
    )
    print()
    print(
        f"converged images (ours: {orun.name}): relative RMSE "
        f"{100 * a['converged_rel_rmse']:.2f} % (2-sigma upper "
        f"bound {100 * a['converged_rel_rmse_upper_2sigma']:.2f} %, target < 2 %); raw RMSE of the two means "
        f"{100 * a['raw_rel_rmse_of_means']:.2f} % (noise included); mean Y {a['mean_y_ours']:.5f} vs "
        f"{a['mean_y_mitsuba']:.5f} ({100 * a['mean_rel_diff']:+.3f} %)"
    )
    if urun is not None:
        u = res["agreement_uniform"]
        print(
            f"ours uniform vs Mitsuba: converged relative RMSE {100 * u['converged_rel_rmse']:.2f} % "
            f"(2-sigma upper {100 * u['converged_rel_rmse_upper_2sigma']:.2f} %)"
        )
    if args.json:
        from warpoptics.film.image import atomic_path

        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(res, indent=2))
    if args.save:
        np.savez_compressed(
            args.save,
            ours=ours.mean(0),
            mitsuba=theirs.mean(0),
            ours_passes=len(ours),
            mitsuba_passes=len(theirs),
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
