"""warpoptics against Mitsuba 3 at equal error on the non-dispersive diamond (issue 7, "Performance").

Scene: ``scenes/bench_diamond.toml`` (Tolkowsky round brilliant, n = 2.4173, studio light as a
lat-long EXR read by both renderers, 256x256, 16 scattering events: our max_depth 16, Mitsuba's
max_depth 17), unpolarized.  Mitsuba gets the scene through ``warpoptics.mitsuba_export``.

Method.  Each renderer renders independent passes (different seeds; ours ``spp`` x
``wavelengths`` stratified samples per pixel, Mitsuba ``--mitsuba-spp`` paths per pixel) for
a time budget, after one untimed warm-up pass (kernel compilation); the passes of the two
renderers alternate, so that both see the same load on a shared machine.  Image quantity: luminance Y.
For unbiased, independent passes the relative RMSE of the mean of k passes against the
renderer's own converged image is sigma_1 / sqrt(k), sigma_1 = sqrt(mean over pixels of the
per-pixel variance of one pass) / mean Y, so the time to reach ``--target`` (1 %) is
``t_pass * (sigma_1 / target)**2`` (reported, with the spp that takes).  Pass sizes matter for
low-discrepancy samplers (our R2 pixel positions; Mitsuba's ``ldsampler``): a pass of N
samples has sigma_1 falling faster than 1/sqrt(N), so each renderer should get the pass size
that minimises its time (ours: about 1 % noise per pass, ``--spp 48`` x 8 wavelengths; Mitsuba
``ldsampler``: 32-64 spp, larger passes measured slower to target).  The 1/sqrt(k) law is
checked on the measured passes: the RMSE between the means of two disjoint halves of the passes
must be sqrt(2) sigma_1 / sqrt(k/2).  When a renderer's passes reach the target themselves the
time is also read off directly.

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


def rel_noise(passes: np.ndarray) -> float:
    """sigma_1: relative RMSE of one pass against the expectation (per-pixel variances)."""
    return float(np.sqrt(passes.var(axis=0, ddof=1).mean()) / passes.mean())


def half_split_check(passes: np.ndarray) -> tuple[float, float]:
    """(measured, predicted) relative RMSE between the means of the two halves."""
    k = len(passes) // 2
    a, b = passes[:k].mean(0), passes[k : 2 * k].mean(0)
    mean = passes.mean()
    measured = float(np.sqrt(((a - b) ** 2).mean()) / mean)
    return measured, float(np.sqrt(2.0 / k) * rel_noise(passes))


def converged_difference(ours: np.ndarray, theirs: np.ndarray) -> dict:
    """Noise-free estimate of the relative RMSE between the converged images (split halves)."""
    ka, kb = len(ours) // 2, len(theirs) // 2
    a1, a2 = ours[:ka].mean(0), ours[ka : 2 * ka].mean(0)
    b1, b2 = theirs[:kb].mean(0), theirs[kb : 2 * kb].mean(0)
    prod = ((a1 - b1) * (a2 - b2)).ravel()
    est, se = float(prod.mean()), float(prod.std(ddof=1) / np.sqrt(prod.size))
    ref = float(theirs.mean())
    raw = float(np.sqrt(((ours.mean(0) - theirs.mean(0)) ** 2).mean()) / ref)
    return {
        "converged_rel_rmse": float(np.sqrt(max(est, 0.0)) / ref),
        "converged_rel_rmse_upper_2sigma": float(np.sqrt(max(est + 2 * se, 0.0)) / ref),
        "raw_rel_rmse_of_means": raw,
        "mean_y_ours": float(ours.mean()),
        "mean_y_mitsuba": ref,
        "mean_rel_diff": float(ours.mean() / ref - 1.0),
    }


def time_to_target(passes: np.ndarray, times: list[float], samples_per_pass: int, target: float) -> dict:
    s1 = rel_noise(passes)
    t_pass = float(np.median(times))
    k = (s1 / target) ** 2
    out = {
        "passes": len(passes),
        "seconds_per_pass": t_pass,
        "samples_per_pass": samples_per_pass,
        "rel_noise_one_pass": s1,
        "passes_to_target": k,
        "seconds_to_target": k * t_pass,
        "samples_to_target": k * samples_per_pass,
    }
    # direct reading when the run itself got there
    if len(passes) >= 2 and s1 / np.sqrt(len(passes)) <= target:
        out["seconds_to_target_measured"] = float(np.sum(times[: int(np.ceil(k))]))
    m, p = half_split_check(passes) if len(passes) >= 4 else (float("nan"), float("nan"))
    out["half_split_rel_rmse_measured"] = m
    out["half_split_rel_rmse_predicted"] = p
    return out


class OursRunner:
    def __init__(self, scene, log):
        import warpoptics as wo

        self.wo, self.scene, self.ims, self.times = wo, scene, [], []
        t0 = time.perf_counter()
        wo.render(scene, seed=10_000)  # warm-up: kernel compilation / loading
        log(f"ours: warm-up pass {time.perf_counter() - t0:.1f} s")

    def step(self):
        t = time.perf_counter()
        img = self.wo.render(self.scene, seed=len(self.ims))
        self.times.append(time.perf_counter() - t)
        self.ims.append(img.xyz[..., 1])


class MitsubaRunner:
    def __init__(
        self, scene, variant: str, spp: int, log, env_step: float = 1.0, sampler: str = "independent"
    ):
        import mitsuba as mi

        from warpoptics import mitsuba_export as mx

        mi.set_variant(variant)
        self.mx, self.scene, self.spp, self.ims, self.times = mx, scene, spp, [], []
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


def run_interleaved(
    ours: OursRunner,
    theirs: MitsubaRunner,
    ours_budget: float,
    theirs_budget: float,
    min_passes: int,
    max_passes: int,
    log,
) -> None:
    """Alternate the two renderers so that both see the same (shared-machine) load: each round
    runs one pass of ours and Mitsuba passes until Mitsuba's time catches up with ours (scaled by
    the ratio of the budgets)."""
    ratio = theirs_budget / max(ours_budget, 1e-9)
    last = time.perf_counter()
    while True:
        t_o, t_m = sum(ours.times), sum(theirs.times)
        more_o = len(ours.ims) < max_passes and (len(ours.ims) < min_passes or t_o < ours_budget)
        more_m = len(theirs.ims) < max_passes and (len(theirs.ims) < min_passes or t_m < theirs_budget)
        if not (more_o or more_m):
            break
        if more_o and (not more_m or t_o * ratio <= t_m):
            ours.step()
        else:
            theirs.step()
        if time.perf_counter() - last > 60:
            last = time.perf_counter()
            log(
                f"ours {len(ours.ims)} passes {sum(ours.times):.0f} s; mitsuba {len(theirs.ims)} passes "
                f"{sum(theirs.times):.0f} s"
            )


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
    ap.add_argument("--spp", type=int, default=48,
                    help="our spp per pass (x the scene's 8 wavelengths: about 1 %% noise per pass)")
    ap.add_argument("--ours-seconds", type=float, default=900.0, help="time budget of our passes")
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

    def log(msg):
        print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)

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
        args.spp = min(args.spp, 2)
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
        f"scene {args.scene}: {w}x{h}, ours {r.spectral} {r.wavelengths} wavelengths x spp {r.spp}, "
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
    orun = OursRunner(scene, log)
    run_interleaved(orun, mr, args.ours_seconds, args.mitsuba_seconds, args.min_passes, args.max_passes, log)
    ours, t_ours = np.array(orun.ims), orun.times
    theirs, t_theirs = np.array(mr.ims), mr.times

    res = {
        "scene": args.scene,
        "width": w,
        "height": h,
        "target": args.target,
        "mitsuba_variant": variant,
        "mitsuba_sampler": args.mitsuba_sampler,
        "ours": time_to_target(ours, t_ours, per_pass, args.target),
        "mitsuba": time_to_target(theirs, t_theirs, args.mitsuba_spp, args.target),
        "agreement": converged_difference(ours, theirs),
    }
    res["speedup_at_target"] = res["mitsuba"]["seconds_to_target"] / res["ours"]["seconds_to_target"]
    o, t, a = res["ours"], res["mitsuba"], res["agreement"]
    print()
    print(
        f"| {w}x{h}, to {100 * args.target:g} % rel. RMSE of Y | warpoptics ({r.spectral}, unpolarized) "
        f"| Mitsuba {variant} |"
    )
    print("|---|---|---|")
    print(f"| samples per pixel per pass | {o['samples_per_pass']} | {t['samples_per_pass']} |")
    print(
        f"| seconds per pass (median of {o['passes']} / {t['passes']}) | {o['seconds_per_pass']:.3f} "
        f"| {t['seconds_per_pass']:.3f} |"
    )
    print(f"| rel. RMSE of one pass | {o['rel_noise_one_pass']:.4f} | {t['rel_noise_one_pass']:.4f} |")
    print(
        f"| half-split check measured / predicted | {o['half_split_rel_rmse_measured']:.4f} / "
        f"{o['half_split_rel_rmse_predicted']:.4f} | {t['half_split_rel_rmse_measured']:.4f} / "
        f"{t['half_split_rel_rmse_predicted']:.4f} |"
    )
    print(f"| samples per pixel to target | {o['samples_to_target']:.0f} | {t['samples_to_target']:.0f} |")
    print(f"| **seconds to target** | **{o['seconds_to_target']:.0f}** | **{t['seconds_to_target']:.0f}** |")
    print(f"| speed-up (Mitsuba time / ours) | {res['speedup_at_target']:.3f} | 1 |")
    print(f"| mean Y | {a['mean_y_ours']:.5f} | {a['mean_y_mitsuba']:.5f} |")
    print()
    print(
        f"converged images: relative RMSE {100 * a['converged_rel_rmse']:.2f} % (2-sigma upper bound "
        f"{100 * a['converged_rel_rmse_upper_2sigma']:.2f} %, target < 2 %); raw RMSE of the two means "
        f"{100 * a['raw_rel_rmse_of_means']:.2f} % (noise included); mean Y differs by "
        f"{100 * a['mean_rel_diff']:+.3f} %"
    )
    if args.json:
        from warpoptics.image import atomic_path

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
