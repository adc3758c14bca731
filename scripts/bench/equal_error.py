"""Equal-error benchmark machinery shared by ``bench_mitsuba.py`` and ``bench_fire.py``.

Each renderer renders independent passes (different seeds or sample offsets); the passes of the
renderers alternate (:func:`run_interleaved`) so that all see the same load on a shared
machine.  For unbiased, independent passes the relative RMSE of the mean of k passes against the
renderer's *own* converged image is ``sigma_1 / sqrt(k)``, with ``sigma_1`` =
sqrt(mean over pixels (and channels) of the per-pixel variance of one pass) / image mean
(:func:`rel_noise`), so the time to a target relative RMSE is ``t_pass * (sigma_1 / target)**2``
when that is one pass or more (:func:`time_to_target`; never extrapolated below one pass: low-
discrepancy and adaptive samplers gain faster than 1/sqrt(N) within a pass).  The 1/sqrt(k) law
is checked on the measured passes by :func:`half_split_check`.

The agreement of two renderers' converged images, free of their noise: with each renderer's
passes split into two independent halves (a1, a2; b1, b2), ``mean((a1 - b1) (a2 - b2))`` is an
unbiased estimate of the mean squared difference of the converged images
(:func:`converged_difference`).

Run a script with ``python scripts/bench/<script>.py``: this directory is then on ``sys.path``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np


def shown(path) -> str:
    """A path as the logs show it: relative to the repository when inside it (no machine paths
    in committed results)."""
    root = Path(__file__).resolve().parents[2]
    p = Path(path).resolve()
    return str(p.relative_to(root)) if p.is_relative_to(root) else str(path)


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


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


def converged_difference(
    ours: np.ndarray,
    theirs: np.ndarray,
    *,
    labels: tuple[str, str] = ("ours", "mitsuba"),
    quantity: str = "y",
) -> dict:
    """Noise-free estimate of the relative RMSE between the converged images (split halves),
    relative to the mean of ``theirs``; pass stacks ``(passes, ...)`` of any trailing shape."""
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
        f"mean_{quantity}_{labels[0]}": float(ours.mean()),
        f"mean_{quantity}_{labels[1]}": ref,
        "mean_rel_diff": float(ours.mean() / ref - 1.0),
    }


def time_to_target(
    passes: np.ndarray,
    times: list[float],
    samples_per_pass: float,
    target: float,
    cpu_times: list[float] | None = None,
) -> dict:
    """Time to ``target`` from independent passes: k = (sigma_1 / target)^2 passes.  When one pass
    is already below the target (k < 1) the time is that of one pass: a smaller pass would not
    reach it in k pass-times (low-discrepancy and adaptive samplers gain faster than 1/sqrt(N)
    within a pass), so fewer-than-one-pass extrapolations are never reported.  ``cpu_times``
    (CPU seconds of each pass, all threads) adds the same figures in CPU seconds."""
    s1 = rel_noise(passes)
    t_pass = float(np.median(times))
    k = (s1 / target) ** 2
    out = {
        "passes": len(passes),
        "seconds_per_pass": t_pass,
        "samples_per_pass": samples_per_pass,
        "rel_noise_one_pass": s1,
        "passes_to_target": k,
        "seconds_to_target": max(k, 1.0) * t_pass,
        "samples_to_target": max(k, 1.0) * samples_per_pass,
        "one_pass_reaches_target": bool(k <= 1.0),
    }
    if cpu_times is not None:
        c_pass = float(np.median(cpu_times))
        out["cpu_seconds_per_pass"] = c_pass
        out["cpu_seconds_to_target"] = max(k, 1.0) * c_pass
    # direct reading when the run itself got there
    if len(passes) >= 2 and s1 / np.sqrt(len(passes)) <= target:
        out["seconds_to_target_measured"] = float(np.sum(times[: int(np.ceil(k))]))
    m, p = half_split_check(passes) if len(passes) >= 4 else (float("nan"), float("nan"))
    out["half_split_rel_rmse_measured"] = m
    out["half_split_rel_rmse_predicted"] = p
    return out


class OursRunner:
    """warpoptics passes of ``scene`` (seed = pass index), after one untimed warm-up pass (kernel
    compilation).  ``quantity`` turns an Image into the array compared (default luminance Y);
    ``times`` are wall seconds, ``cpu_times`` CPU seconds of this process (all threads)."""

    def __init__(self, scene, log, name="ours", quantity: Callable | None = None, device=None):
        import warpoptics as wo

        self.wo, self.scene, self.name, self.device = wo, scene, name, device
        self.quantity = quantity or (lambda img: img.xyz[..., 1])
        self.ims: list[np.ndarray] = []
        self.times: list[float] = []
        self.cpu_times: list[float] = []
        t0 = time.perf_counter()
        wo.render(scene, seed=10_000, device=device)  # warm-up: kernel compilation / loading
        log(f"{name}: warm-up pass {time.perf_counter() - t0:.1f} s")

    def step(self):
        t, c = time.perf_counter(), time.process_time()
        img = self.wo.render(self.scene, seed=len(self.ims), device=self.device)
        self.times.append(time.perf_counter() - t)
        self.cpu_times.append(time.process_time() - c)
        self.ims.append(self.quantity(img))


def run_interleaved(runners: list, budgets: list[float], min_passes: int, max_passes: int, log) -> None:
    """Alternate the renderers so that all see the same (shared-machine) load: the next pass is
    always the one of the renderer furthest behind its budget (time spent / budget)."""
    last = time.perf_counter()
    while True:
        todo = [
            (sum(r.times) / max(b, 1e-9), i)
            for i, (r, b) in enumerate(zip(runners, budgets, strict=True))
            if len(r.ims) < max_passes and (len(r.ims) < min_passes or sum(r.times) < b)
        ]
        if not todo:
            break
        runners[min(todo)[1]].step()
        if time.perf_counter() - last > 60:
            last = time.perf_counter()
            log("; ".join(f"{r.name} {len(r.ims)} passes {sum(r.times):.0f} s" for r in runners))
