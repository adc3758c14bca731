"""What a spectral-bundle lane costs: the per-lane laws, timed one by one.

A bundle (``stages/bundle.py``) traces one path tree for several wavelengths; every lane pays,
at every node, its own interface event and, at every leaf, its own environment lookup and film
update.  This script times those laws alone on the CPU device (one thread per call of a kernel
that evaluates the law 16 times per thread over 2^20 threads, random inputs drawn in the kernel;
the "rng only" row is the cost of drawing them, to subtract):

- ``backward_isotropic`` (``optics.interface``): air -> diamond, polarized, both children;
- ``fresnel_amplitudes`` (``optics.fresnel``) alone: the event solves it twice;
- ``environment_coefficients`` (``stages.environment``) on the benchmark's lat-long studio map,
  for random directions (cache misses over the 6 MB map) and for nearly equal ones (what a
  bundle's lanes and neighbouring pixels see);
- ``environment_basis`` + ``cmf_xyz`` (the spectral tables a leaf point would add);
- ``add_leaf`` (``film.leaf``), polarized.

Then the whole bundle per pixel position on the fire benchmark stone
(``fire_convergence.scene_for``, 32x32, 8 spp, one thread) for 1, 2, 4, 8 and 16 lanes and the
clear twin: the marginal cost of a lane against the cost of the laws above.

    python scripts/bench/bench_lane_cost.py [--json scripts/bench/results/bench_lane_cost.json]
    python scripts/bench/bench_lane_cost.py --only bundle:8 --spp 48   # one position setting
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np
import warp as wp

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fire_convergence import scene_for  # noqa: E402

from warpoptics.film.leaf import add_leaf  # noqa: E402
from warpoptics.optics.branches import Cand  # noqa: E402
from warpoptics.optics.fresnel import fresnel_amplitudes  # noqa: E402
from warpoptics.optics.interface import backward_isotropic  # noqa: E402
from warpoptics.optics.jones import Jones, jones_zero  # noqa: E402
from warpoptics.pipelines.render import Renderer  # noqa: E402
from warpoptics.spectra import SpectralTables, cmf_xyz  # noqa: E402
from warpoptics.stages.environment import Environment, environment_basis, environment_coefficients  # noqa: E402

wp.set_module_options({"enable_backward": False})

THREADS = 1 << 20
REP = 16


@wp.func
def _random_direction(rng: wp.uint32):
    d = wp.normalize(wp.vec3f(wp.randf(rng) - 0.5, wp.randf(rng) - 0.5, wp.randf(rng) - 0.5))
    return d, rng


@wp.kernel
def k_rng(out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    s = float(0.0)
    for _k in range(REP):
        d, rng = _random_direction(rng)
        s += d[0]
    out[i] = s


@wp.kernel
def k_event(out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    s = float(0.0)
    cand = Cand()
    nrm = wp.vec3f(0.0, 0.0, 1.0)
    for _k in range(REP):
        d = wp.normalize(wp.vec3f(wp.randf(rng) - 0.5, wp.randf(rng) - 0.5, -1.0))
        m = Jones()
        m.re = wp.mat22(1.0, 0.0, 0.0, 1.0)
        bx = wp.normalize(wp.cross(d, wp.vec3f(0.0, 1.0, 0.0)))
        n_b = wp.vec2f(2.4 + 0.01 * wp.randf(rng), 0.0)
        cand, e, count = backward_isotropic(
            cand, m, 1.0, bx, d, nrm, nrm, wp.vec2f(1.0, 0.0), n_b, wp.vec3f(), 1e-4, -1, 0, 1, 1
        )
        s += e[0] + float(count)
    out[i] = s


@wp.kernel
def k_fresnel(out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    s = float(0.0)
    for _k in range(REP):
        c = wp.randf(rng)
        f = fresnel_amplitudes(c, wp.vec2f(1.0, 0.0), wp.vec2f(2.4 + 0.01 * wp.randf(rng), 0.0))
        s += f.rs[0] + f.tp[0] + wp.randf(rng)
    out[i] = s


@wp.kernel
def k_env(env: Environment, coherent: int, out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    s = float(0.0)
    for _k in range(REP):
        d, rng = _random_direction(rng)
        if coherent != 0:  # nearly equal directions: the same three draws, a thousandth apart
            d = wp.normalize(wp.vec3f(0.3 + 0.001 * d[0], 0.2, 0.5 + 0.001 * float(i % 64)))
        s += environment_coefficients(env, d)[0]
    out[i] = s


@wp.kernel
def k_tables(env: Environment, tables: SpectralTables, out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    s = float(0.0)
    for _k in range(REP):
        wl = 380.0 + 400.0 * (wp.randf(rng) + wp.randf(rng) + wp.randf(rng)) / 3.0
        s += environment_basis(env, tables, wl)[0] + cmf_xyz(tables, wl)[1]
    out[i] = s


@wp.kernel
def k_leaf(env: Environment, out: wp.array(dtype=float)):
    i = wp.tid()
    rng = wp.rand_init(7, i)
    ax = jones_zero()
    ay = jones_zero()
    az = jones_zero()
    sx = wp.vec3f()
    for _k in range(REP):
        d, rng = _random_direction(rng)
        m = Jones()
        m.re = wp.mat22(1.0, 0.1, 0.0, 1.0)
        m.im = wp.mat22(0.0, 0.1, 0.0, 0.0)
        bx = wp.normalize(wp.cross(d, wp.vec3f(0.0, 0.0, 1.0)))
        ax, ay, az, sx = add_leaf(ax, ay, az, sx, 1, m, 1.0, env.polarizer, -d, bx, wp.vec3f(1.0, 1.0, 1.0))
    out[i] = ax.re[0, 0] + ay.re[0, 0] + az.re[1, 1]


def time_kernel(kernel, inputs, out) -> float:
    """ns per law evaluation: the best of three launches (after a warm-up)."""
    wp.launch(kernel, dim=THREADS, inputs=[*inputs, out], device="cpu")
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        wp.launch(kernel, dim=THREADS, inputs=[*inputs, out], device="cpu")
        wp.synchronize()
        best = min(best, time.perf_counter() - t0)
    return 1e9 * best / (THREADS * REP)


def position_cost(est: str, lanes: int, spp: int, res: int = 32) -> tuple[float, float]:
    """(process CPU microseconds, rays) per pixel position of the fire benchmark stone, one thread."""
    sc = scene_for(est, res, lanes, lanes).with_overrides({"render.spp": spp, "render.seed": 3})
    rr = Renderer(sc)
    rr.load_kernels()
    t0 = time.process_time()
    img = rr.run(threads=1)
    n = spp * res * res
    return 1e6 * (time.process_time() - t0) / n, float(img.stats["rays"]) / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", type=Path)
    ap.add_argument(
        "--only",
        metavar="ESTIMATOR:LANES",
        help="time one pixel-position setting alone (e.g. bundle:8, clear:1), for before/after runs"
        " alternated between two checkouts",
    )
    ap.add_argument("--spp", type=int, default=8, help="samples per pixel of the position timings")
    args = ap.parse_args(argv)
    if args.only:
        est, lanes = args.only.split(":")
        us, rays = position_cost(est, int(lanes), args.spp)
        print(f"{args.only} {us:.3f} us per pixel position, {rays:.1f} rays", flush=True)
        return 0
    print(f"bench_lane_cost: load average {os.getloadavg()[0]:.2f}", flush=True)
    r = Renderer(scene_for("bundle", 32, 8, 8))
    env, tables = r.environment.struct, r.tables
    out = wp.zeros(THREADS, dtype=float, device="cpu")
    laws = {}
    for name, kernel, inputs in (
        ("rng only (one random direction)", k_rng, []),
        ("backward_isotropic", k_event, []),
        ("fresnel_amplitudes", k_fresnel, []),
        ("environment_coefficients, random directions", k_env, [env, 0]),
        ("environment_coefficients, nearly equal directions", k_env, [env, 1]),
        ("environment_basis + cmf_xyz", k_tables, [env, tables]),
        ("add_leaf, polarized", k_leaf, [env]),
    ):
        laws[name] = time_kernel(kernel, inputs, out)
        print(f"  {name:52s} {laws[name]:6.1f} ns per call (inputs included)", flush=True)
    positions = {}
    for est, lanes in (
        ("bundle", 1),
        ("bundle", 2),
        ("bundle", 4),
        ("bundle", 8),
        ("bundle", 16),
        ("clear", 1),
    ):
        us, rays = position_cost(est, lanes, args.spp)
        key = f"{est} {lanes} lanes" if est == "bundle" else "clear twin, 1 wavelength tree"
        positions[key] = {"us_per_position": us, "rays_per_position": rays}
        print(f"  {key:30s} {us:6.2f} us per pixel position, {rays:5.1f} rays", flush=True)
    one, sixteen = positions["bundle 1 lanes"], positions["bundle 16 lanes"]
    marginal = (sixteen["us_per_position"] - one["us_per_position"]) / 15.0
    share = marginal / one["us_per_position"]
    print(f"  marginal lane: {marginal:.2f} us per position ({share:.2f} of one lane's trace)")
    print(f"load average after {os.getloadavg()[0]:.2f}")
    if args.json:
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp, open(tmp, "w") as f:
            json.dump(
                {"ns_per_call": laws, "positions": positions, "marginal_lane_us": marginal}, f, indent=1
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
