"""Speed-up of tiled CPU launches from a thread pool over a single Warp CPU launch.

Warp runs one CPU launch on one thread; `warpoptics.device.launch_tiled` splits the range into
tiles launched from a pool sized to the cores.  The workload is the wavelength sampling and
CIE lookup the renderer runs per ray, repeated to make the launch long enough to time.

    python scripts/bench/bench_tiles.py [--n 2000000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import warp as wp

from warpoptics import device as wodev
from warpoptics.spectra import SpectralTables, sample_wavelength, spectral_tables


@wp.kernel
def _workload(offset: int, u: wp.array(dtype=wp.float32), t: SpectralTables, out: wp.array(dtype=wp.vec3f)):
    i = wp.tid() + offset
    acc = wp.vec3f(0.0, 0.0, 0.0)
    for s in range(45):
        wl, w = sample_wavelength(t, 3, u[i], s, 45)
        acc = acc + w * wp.sin(wl * 0.01)
    out[i] = acc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    dev = wodev.get_device("cpu")
    rng = np.random.default_rng(0)
    u = wp.array(rng.random(args.n).astype(np.float32), device=dev)
    out = wp.zeros(args.n, dtype=wp.vec3f, device=dev)
    tables = spectral_tables(dev)
    wodev.launch_tiled(_workload, 1000, [u, tables, out], device=dev, threads=1)  # compile

    def timed(threads):
        best = np.inf
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            wodev.launch_tiled(_workload, args.n, [u, tables, out], device=dev, threads=threads)
            best = min(best, time.perf_counter() - t0)
        return best

    t1 = timed(1)
    ref = out.numpy().copy()
    threads = wodev.cpu_threads()
    tn = timed(threads)
    same = np.array_equal(ref, out.numpy())
    print(f"elements {args.n}, 45 stratified samples each")
    print(f"single launch (1 thread):   {t1 * 1e3:8.1f} ms")
    print(f"tiled, {threads} threads:        {tn * 1e3:8.1f} ms")
    print(f"speed-up: {t1 / tn:.2f}x  (identical results: {same})")


if __name__ == "__main__":
    main()
