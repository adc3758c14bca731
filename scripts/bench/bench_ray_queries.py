"""Rays per second of the closest-hit queries on a round brilliant: BVH vs convex facet planes.

Rays: half from outside (origins on a sphere of radius 2 x diameter, aimed at random points of
the stone's bounding box; about 60 % hit), half from inside (uniform in the stone, random
directions; all hit), the mix a gem tracer sees.  Timings are the best of ``--repeat`` runs of
the warm kernel (compile excluded, reported separately) on one thread and on all threads
(``device.launch_tiled``); on one CPU thread the thread's CPU time is reported too (robust to
other processes sharing the machine).  Then the inside half alone through the exit query
(``object_exit_hit``: the tracer's query after a refraction into the stone).  Optionally the
same rays through Embree (PyPI ``embreex``, one ``rtcIntersect1`` per ray on one thread) as a
reference for what a CPU BVH can do.

    python scripts/bench/bench_ray_queries.py [--rays 1000000] [--repeat 3] [--no-embree]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import warp as wp

import warpoptics as wo
from warpoptics.geometry import cuts, query


def make_rays(mesh, n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    planes = mesh.metadata["planes"]
    lo, hi = mesh.bounds
    diam = float(np.max(hi - lo))
    n_out = n // 2
    o = rng.normal(size=(n_out, 3))
    o = o / np.linalg.norm(o, axis=1, keepdims=True) * 2.0 * diam
    target = rng.uniform(lo, hi, size=(n_out, 3))
    d = target - o
    inside = np.empty((0, 3))
    while len(inside) < n - n_out:
        p = rng.uniform(lo, hi, size=(2 * (n - n_out), 3))
        ok = np.all(p @ planes[:, :3].T - planes[:, 3] < -1e-6 * diam, axis=1)
        inside = np.concatenate([inside, p[ok]])
    o = np.concatenate([o, inside[: n - n_out]])
    d = np.concatenate([d, rng.normal(size=(n - n_out, 3))])
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return o.astype(np.float32), d.astype(np.float32)


def _dt_summary(t_a, t_b, size: float, cos) -> str:
    """Largest |dt| (mm), and largest |dt|/t where t > size/10 and the incidence cosine > 0.05
    (rays starting next to a facet have tiny t, where only the absolute error means something;
    grazing rays amplify float32 round-off by 1/cos)."""
    dt = np.abs(t_a.astype(np.float64) - t_b)
    far = (t_b > 0.1 * size) & (cos > 0.05)
    return f"max |dt| {dt.max():.2e} mm, max |dt|/t (t > D/10, cos > 0.05) {np.max(dt[far] / t_b[far]):.2e}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--diameter", type=float, default=6.5)
    ap.add_argument("--girdle-facets", type=int, default=16)
    ap.add_argument("--no-embree", action="store_true")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    dev = wo.device.get_device(args.device)
    mesh = cuts.round_brilliant(args.diameter, girdle_facets=args.girdle_facets)
    o_np, d_np = make_rays(mesh, args.rays)
    n = len(o_np)
    t0 = time.perf_counter()
    scene = query.GeometryScene([mesh], device=dev)
    origins = wp.array(o_np, dtype=wp.vec3f, device=dev)
    dirs = wp.array(d_np, dtype=wp.vec3f, device=dev)
    tmax = wp.full(n, 1e30, dtype=wp.float32, device=dev)
    out = [
        wp.zeros(n, dtype=wp.float32, device=dev),
        wp.zeros(n, dtype=wp.int32, device=dev),
        wp.zeros(n, dtype=wp.int32, device=dev),
        wp.zeros(n, dtype=wp.int32, device=dev),
        wp.zeros(n, dtype=wp.vec3f, device=dev),
    ]
    scene.launch_closest_hit(origins[:1], dirs[:1], tmax[:1], [a[:1] for a in out], threads=1)
    wp.synchronize_device(dev)
    setup = time.perf_counter() - t0
    cores = wo.device.cpu_threads()
    print(
        f"round brilliant {args.diameter} mm: {len(mesh.faces)} triangles, "
        f"{len(mesh.metadata['planes'])} facet "
        f"planes; {n} rays (half outside, half inside); device {dev.alias}, {cores} threads"
    )
    print(f"scene build + kernel load/compile: {setup:.2f} s")
    results = {}
    cpu_rate = {}
    threads_list = [1] if not dev.is_cpu or cores == 1 else [1, cores]
    for mode in ("bvh", "convex"):
        for threads in threads_list:
            best = best_cpu = np.inf
            for _ in range(args.repeat):
                t0, c0 = time.perf_counter(), time.thread_time()
                scene.launch_closest_hit(origins, dirs, tmax, out, mode=mode, threads=threads)
                wp.synchronize_device(dev)
                best = min(best, time.perf_counter() - t0)
                best_cpu = min(best_cpu, time.thread_time() - c0)
            results[(mode, threads)] = (n / best, out[0].numpy().copy(), out[2].numpy().copy())
            cpu_rate[(mode, threads)] = n / best_cpu
            if mode == "convex" and threads == 1:
                cos_all = np.abs(np.einsum("ij,ij->i", out[4].numpy(), d_np))
            # one thread on the CPU: the launch runs in this thread, so its CPU time is the kernel's
            # work, immune to other processes sharing the cores
            cpu = f", CPU time {n / best_cpu / 1e6:.2f} Mrays/s" if dev.is_cpu and threads == 1 else ""
            print(
                f"  {mode:7s} {threads:2d} thread(s): {n / best / 1e6:8.2f} Mrays/s  "
                f"({best * 1e3:.1f} ms{cpu})"
            )
    tb, fb = results[("bvh", 1)][1:]
    tc, fc = results[("convex", 1)][1:]
    hit = (fb >= 0) & (fc >= 0)
    print(
        f"  agreement: hit/miss {np.mean((fb >= 0) == (fc >= 0)):.6f}, "
        f"facet {np.mean(fb[hit] == fc[hit]):.6f}, "
        f"{_dt_summary(tb[hit], tc[hit], args.diameter, cos_all[hit])}"
    )
    for threads in threads_list[1:]:
        print(
            f"  speed-up on {threads} threads: "
            f"bvh {results[('bvh', threads)][0] / results[('bvh', 1)][0]:.2f}x, "
            f"convex {results[('convex', threads)][0] / results[('convex', 1)][0]:.2f}x"
        )
    print(f"  convex / bvh (1 thread, CPU time): {cpu_rate[('convex', 1)] / cpu_rate[('bvh', 1)]:.2f}x")
    # rays known to be inside (the tracer's case after refraction): object_exit_hit
    half = n // 2
    o_in, d_in = origins[half:], dirs[half:]
    obj = wp.zeros(n - half, dtype=wp.int32, device=dev)
    out_in = [a[half:] for a in out]
    rates = {}
    for mode in ("bvh", "convex"):
        best_cpu = np.inf
        for _ in range(args.repeat):
            c0 = time.thread_time()
            scene.launch_exit_hit(o_in, d_in, obj, tmax[half:], out_in, mode=mode, threads=1)
            wp.synchronize_device(dev)
            best_cpu = min(best_cpu, time.thread_time() - c0)
        rates[mode] = (n - half) / best_cpu
        print(f"  inside rays, exit query, {mode:6s} 1 thread: {rates[mode] / 1e6:6.2f} Mrays/s (CPU time)")
    print(f"  inside rays, exit query, convex / bvh: {rates['convex'] / rates['bvh']:.2f}x")
    if not args.no_embree:
        try:
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh
        except ImportError:
            print("  embree: not installed (pip install embreex)")
            return 0
        es = rtcore_scene.EmbreeScene()
        TriangleMesh(
            scene=es,
            vertices=np.asarray(mesh.vertices, dtype=np.float32),
            indices=np.asarray(mesh.faces, dtype=np.int32),
        )
        best = best_cpu = np.inf
        for _ in range(args.repeat):
            t0, c0 = time.perf_counter(), time.thread_time()
            res = es.run(o_np, d_np, output=1)
            best = min(best, time.perf_counter() - t0)
            best_cpu = min(best_cpu, time.thread_time() - c0)
        prim = np.asarray(res["primID"])
        tfar = np.asarray(res["tfar"])
        eh = prim >= 0
        face_facet = mesh.metadata["face_facet"]
        both = eh & (fb >= 0)
        print(
            f"  embree   1 thread(s): {n / best / 1e6:8.2f} Mrays/s  "
            f"({best * 1e3:.1f} ms, CPU time {n / best_cpu / 1e6:.2f} Mrays/s; includes embreex's "
            f"NumPy overhead)"
        )
        print(
            f"  embree vs bvh: hit/miss {np.mean(eh == (fb >= 0)):.6f}, facet "
            f"{np.mean(face_facet[prim[both]] == fb[both]):.6f}, "
            f"{_dt_summary(tfar[both], tb[both], args.diameter, cos_all[both])}"
        )
    return 0


if __name__ == "__main__":
    os.environ.setdefault("PYTHONWARNINGS", "ignore")
    raise SystemExit(main())
