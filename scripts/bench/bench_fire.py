"""Fire at speed: the dispersive, polarized diamond against its clear twin and a peer.

Scenes: ``scenes/bench_fire.toml`` (Tolkowsky round brilliant, library ``diamond`` with its
dispersion, ``absorption_scale = 0``, polarized, the studio lat-long EXR, 256x256, 16 scattering
events) and ``scenes/bench_fire_clear.toml`` (the same with a constant index, 2.4173).  Peer:
``indicatrix`` 0.9.0 (crates.io, MIT; spectral -- 8 hero-wavelength channels --, Stokes-Mueller
polarized, dispersive), through the bench-only binary in ``scripts/bench/indicatrix_peer/``
over its public CPU frame tracer, given the same stone (our mesh, exported as OBJ, read back
as its facet planes), the same camera and the same map texels (mirrored left-right and the
scene turned into indicatrix's y-up frame by a proper rotation, so that every direction sees
the same texel under both renderers' bilinear lookups).  Build it first:

    cargo build --release --manifest-path scripts/bench/indicatrix_peer/Cargo.toml

Method (``equal_error.py``): each renderer is measured against its *own* converged image.  The
three renderers' passes alternate in one run (the next pass is always the one of the renderer
furthest behind its time budget), so that all see the same load; each pass is independent
(ours: a new seed; indicatrix: a disjoint range of sample indices).  Image quantity: linear
sRGB, all pixels and channels, no gamut clipping.  From the per-pixel variance of one pass,
sigma_1 (relative RMSE of one pass against the expectation), the time to a target relative RMSE
is t_pass (sigma_1 / target)^2 (never less than one pass), reported for 5, 2 and 1 % in wall
and CPU seconds; the 1/sqrt(k) law is checked on the passes (two halves' RMSE, measured vs
predicted).  Wall seconds of a pass: ours ``wo.render``; indicatrix the trace itself, timed by
the binary (scene and map loading excluded).  CPU seconds: ``time.process_time`` of this
process for ours (all threads), the child's user + system time (``getrusage``) for indicatrix.
Both use every core: warpoptics its tile pool, indicatrix one interleaved partition per thread.
The converged images are also compared (split halves, noise-free): ours dispersive vs
indicatrix (the fire-at-speed target's 10 %), and our clear twin vs our dispersive render (what the fire
changes).  XYZ units: indicatrix's XYZ are divided by the Y it gives a white (1, 1, 1) texel
seen directly, since ours gives that texel Y = 1.

    python scripts/bench/bench_fire.py --json scripts/bench/results/bench_fire_256.json \\
        --log scripts/bench/results/bench_fire_256.log          # the full run (hours)
    python scripts/bench/bench_fire.py --quick                 # seconds; skips a missing peer
    python scripts/bench/bench_fire.py --ours-seconds 900 --clear-seconds 300 --peer-seconds 3600
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from equal_error import (  # noqa: E402
    OursRunner,
    converged_difference,
    run_interleaved,
    shown,
    time_to_target,
)

ROOT = Path(__file__).resolve().parents[2]
PEER_DIR = ROOT / "scripts" / "bench" / "indicatrix_peer"
PEER_BIN = PEER_DIR / "target" / "release" / "indicatrix_peer"
TARGETS = (0.05, 0.02, 0.01)

#: world (z up) -> indicatrix (y up), a proper rotation: X = -y, Y = z, Z = -x.  indicatrix's
#: lat-long lookup (u = atan2(X, Z) / 2 pi, v = acos(Y) / pi, renderer/env_map.rs) then reads
#: u = 1 - u_blender, v = v_blender: our map mirrored left-right is the same texel everywhere.
TO_PEER = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])


def linear_srgb(xyz: np.ndarray) -> np.ndarray:
    from warpoptics.color import xyz_to_srgb_linear

    return xyz_to_srgb_linear(xyz)


def write_pfm(path: Path, rgb: np.ndarray) -> None:
    """A little-endian 3-channel PFM (rows stored bottom to top)."""
    h, w = rgb.shape[:2]
    data = np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes()
    Path(path).write_bytes(f"PF\n{w} {h}\n-1.0\n".encode("ascii") + data)  # not-a-replace: peer scratch


def read_pfm(path: Path) -> np.ndarray:
    raw = Path(path).read_bytes()
    head = raw.split(b"\n", 3)
    w, h = (int(x) for x in head[1].split())
    little = float(head[2]) < 0
    img = np.frombuffer(head[3], dtype="<f4" if little else ">f4", count=w * h * 3).reshape(h, w, 3)
    return img[::-1].astype(np.float64)


def facet_planes(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(n, d) rows, n the outward unit normal, n . x + d <= 0 inside, of a convex mesh: one per
    set of coplanar triangles (normals within 1e-5, offsets within 1e-5 of the size)."""
    tri = vertices[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(n, axis=1)
    keep = area > 1e-12 * area.max()
    n = n[keep] / area[keep, None]
    d = -np.einsum("ij,ij->i", n, tri[keep, 0])
    size = float(np.ptp(vertices, axis=0).max())
    planes: list[np.ndarray] = []
    for row in np.column_stack([n, d]):
        if not any(np.abs(p[:3] - row[:3]).max() < 1e-5 and abs(p[3] - row[3]) < 1e-5 * size for p in planes):
            planes.append(row)
    out = np.array(planes)
    # convexity: every vertex inside or on every plane
    viol = (vertices @ out[:, :3].T + out[:, 3]).max()
    if viol > 1e-4 * size:
        raise ValueError(f"the stone is not convex (a vertex {viol:g} mm outside a facet plane)")
    return out


def export_peer_scene(scene, directory: Path, *, index: float | None = None) -> Path:
    """indicatrix_peer's scene file (and its map PFM, and the stone as OBJ) for ``scene``;
    ``index``: indicatrix's diamond with this constant index instead of its dispersion."""
    import trimesh

    from warpoptics.film.image import read_image
    from warpoptics.pipelines.objects import build_objects

    built = build_objects(scene.objects, file=scene.path)
    if len(built.meshes) != 1:
        raise ValueError("the peer renders one stone")
    mesh, xf = built.meshes[0]
    verts = np.asarray(mesh.vertices, dtype=np.float64) @ xf[:3, :3].T + xf[:3, 3]
    obj = directory / "stone.obj"
    trimesh.Trimesh(verts, np.asarray(mesh.faces), process=False).export(obj)  # not-a-replace: peer scratch
    back = trimesh.load(obj, process=False)  # the peer's stone is the exported file's
    planes = facet_planes(np.asarray(back.vertices, np.float64), np.asarray(back.faces))

    light = scene.lights[0]
    if light.map in ("studio", "dome", "sky", "constant"):
        raise ValueError("the peer needs a lat-long map file")
    if light.convention != "blender" or light.rotation_deg != 0.0 or tuple(light.tint) != (1.0, 1.0, 1.0):
        raise ValueError("the peer export supports the default map placement only (blender, no rotation)")
    texels, _ = read_image(light.map)
    write_pfm(directory / "env.pfm", texels[:, ::-1, :3] * float(light.intensity))

    cam = scene.camera
    pos = np.asarray(cam.position, np.float64)
    fwd = np.asarray(cam.look_at, np.float64) - pos
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, np.asarray(cam.up, np.float64))
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    # Pixel centres: indicatrix's frame tracer jitters by [-0.5, 0.5) around the integer raster
    # point (optics/raytracer/sampling.rs, sample_draws; camera.rs, generate_ray), ours by [0, 1)
    # (pixel centre at x + 0.5).  Its ray is normalize(forward + right u + up v), linear in the
    # raster point, so moving its `forward` by half a pixel (right a t / W, down t / H) puts its
    # pixels where ours are.  Without it the two images are half a pixel apart: on this stone's
    # facet pattern about 130 % relative RMSE at 32x32 with the means equal.
    tan_y = float(np.tan(np.radians(cam.fov) / 2))
    aspect = cam.width / cam.height
    fwd_peer = fwd + right * (aspect * tan_y / cam.width) - up * (tan_y / cam.height)
    vec = [TO_PEER @ v for v in (pos, fwd_peer, right, up)]
    lines = [
        f"# {scene.path}: the scene in indicatrix's y-up frame (scripts/bench/bench_fire.py)",
        f"width {cam.width}",
        f"height {cam.height}",
        f"max_bounces {scene.render.max_depth}",
        "material Diamond",
        *([f"index {index:.9g}"] if index is not None else []),
        "camera " + " ".join(f"{x:.9g}" for v in vec for x in v) + f" {tan_y:.9g}",
        f"env {directory / 'env.pfm'}",
    ]
    for p in planes:
        n = TO_PEER @ p[:3]
        lines.append(f"plane {n[0]:.9g} {n[1]:.9g} {n[2]:.9g} {p[3]:.9g}")
    path = directory / "scene.txt"
    path.write_text("\n".join(lines) + "\n")  # not-a-replace: the peer's scratch scene
    return path


class PeerRunner:
    """indicatrix passes of ``spp`` samples each, through ``indicatrix_peer``."""

    def __init__(
        self,
        scene,
        binary: Path,
        spp: int,
        directory: Path,
        log,
        threads: int | None = None,
        *,
        index: float | None = None,
        name: str = "indicatrix",
    ):
        self.binary, self.spp, self.name = str(binary), int(spp), name
        self.threads = threads or os.cpu_count() or 1
        self.dir = directory
        directory.mkdir(parents=True, exist_ok=True)
        self.scene_file = export_peer_scene(scene, directory, index=index)
        self.ims: list[np.ndarray] = []
        self.times: list[float] = []
        self.cpu_times: list[float] = []
        out = subprocess.run(
            [self.binary, str(self.scene_file), "--calibrate"], capture_output=True, text=True, check=True
        ).stdout
        self.white_xyz = np.array([float(x) for x in out.split()[1:4]])
        log(f"{name}: white texel XYZ {self.white_xyz} (ours: Y = 1); {self.threads} threads")
        t0 = time.perf_counter()
        self._run(10_000_000, 1)  # warm-up (page cache, first-touch)
        log(f"{name}: warm-up pass {time.perf_counter() - t0:.1f} s")

    def _run(self, offset: int, spp: int):
        out = self.dir / "pass.pfm"
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(
            [self.binary, str(self.scene_file), "--spp", str(spp), "--offset", str(offset), "--out", str(out)]
            + ["--threads", str(self.threads)],
            capture_output=True,
            text=True,
            check=True,
        )
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        seconds = float(proc.stdout.split("seconds")[1].split()[0])
        return read_pfm(out) / self.white_xyz[1], seconds, cpu

    def step(self):
        xyz, seconds, cpu = self._run(len(self.ims) * self.spp, self.spp)
        self.times.append(seconds)
        self.cpu_times.append(cpu)
        self.ims.append(linear_srgb(xyz))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "bench_fire.toml"))
    ap.add_argument("--clear-scene", default=str(ROOT / "scenes" / "bench_fire_clear.toml"))
    ap.add_argument("--quick", action="store_true", help="smoke run: 32x32, a few small passes")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--spp", type=int, help="our dispersive spp per pass (default: the scene's)")
    ap.add_argument("--clear-spp", type=int, help="our clear spp per pass (default: the scene's)")
    ap.add_argument("--peer-spp", type=int, default=256, help="indicatrix spp per pass")
    ap.add_argument("--ours-seconds", type=float, default=1800.0, help="wall budget of our dispersive passes")
    ap.add_argument("--clear-seconds", type=float, default=300.0, help="wall budget of our clear passes")
    ap.add_argument("--peer-seconds", type=float, default=3600.0, help="wall budget of indicatrix's passes")
    ap.add_argument("--min-passes", type=int, default=4)
    ap.add_argument("--max-passes", type=int, default=100_000)
    ap.add_argument("--peer-bin", default=str(PEER_BIN))
    ap.add_argument("--peer-threads", type=int, help="indicatrix threads (default: the CPU count)")
    ap.add_argument("--no-peer", action="store_true", help="run without indicatrix")
    ap.add_argument(
        "--peer-clear-seconds",
        type=float,
        default=0.0,
        help="also run indicatrix on the clear twin (its diamond at the constant index) for this budget",
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a setting of our dispersive scene only (TOML value), e.g. render.estimator=beam",
    )
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--log", help="also write this log here")
    ap.add_argument("--save", help="write the mean images (linear sRGB) to this .npz")
    args = ap.parse_args(argv)

    log_lines: list[str] = []

    def log(msg):
        line = f"[{time.strftime('%H:%M:%S')}] {msg}"
        log_lines.append(line)
        print(line, flush=True)

    import warpoptics as wo
    from warpoptics.pipelines.objects import build_objects

    over: dict = {}
    if args.quick:
        over.update({"camera.width": 32, "camera.height": 32, "render.spp": 4})
        args.peer_spp = min(args.peer_spp, 8)
        args.ours_seconds = min(args.ours_seconds, 3.0)
        args.clear_seconds = min(args.clear_seconds, 2.0)
        args.peer_seconds = min(args.peer_seconds, 3.0)
        args.min_passes = min(args.min_passes, 4)
    for key, val in (("camera.width", args.width), ("camera.height", args.height)):
        if val is not None:
            over[key] = val
    scenes = {}
    for name, path, spp in (("ours", args.scene, args.spp), ("clear", args.clear_scene, args.clear_spp)):
        s = wo.Scene.load(path)
        o = dict(over)
        m = s.lights[0].map
        if m not in ("studio", "dome", "sky", "constant") and not Path(m).is_absolute():
            o["light.0.map"] = str(ROOT / m)  # the scene's map path is relative to the repository root
        if spp is not None:
            o["render.spp"] = spp
        if name == "ours":
            for kv in args.set:
                key, _, value = kv.partition("=")
                o[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        scenes[name] = s.with_overrides(o)
    sc = scenes["ours"]
    r = sc.render
    w, h = sc.camera.width, sc.camera.height
    log(
        f"scene {shown(args.scene)}: {w}x{h}, {r.spectral} {r.wavelengths} wavelengths x spp {r.spp}"
        f"{' adaptive' if r.adaptive else ''}{' pixel beams' if r.estimator == 'beam' else ''}, "
        f"polarization {r.polarization}, "
        f"max_depth {r.max_depth}, split_threshold {r.split_threshold}; "
        f"clear twin {shown(args.clear_scene)} spp {scenes['clear'].render.spp}; cpu cores {os.cpu_count()}"
    )
    res: dict = {
        "command": " ".join(
            ["python", "scripts/bench/bench_fire.py", *(argv if argv is not None else sys.argv[1:])]
        ),
        "scene": shown(args.scene),
        "clear_scene": shown(args.clear_scene),
        "width": w,
        "height": h,
        "targets": list(TARGETS),
        "quantity": "linear sRGB, all pixels and channels; rel. RMSE against the own converged image",
        "cpu_count": os.cpu_count(),
    }

    def quantity(img):
        return linear_srgb(img.xyz)

    runners = [OursRunner(sc, log, name="ours dispersive", quantity=quantity)]
    budgets = [args.ours_seconds]
    runners.append(OursRunner(scenes["clear"], log, name="ours clear", quantity=quantity))
    budgets.append(args.clear_seconds)
    peer_dir = tempfile.TemporaryDirectory(prefix="bench_fire_peer_")
    peer = None
    if args.no_peer:
        res["peer"] = "not run (--no-peer)"
    elif not Path(args.peer_bin).exists():
        msg = f"indicatrix peer not built ({args.peer_bin}); skipped"
        log(msg + f": cargo build --release --manifest-path {PEER_DIR / 'Cargo.toml'}")
        res["peer"] = msg
    else:
        peer = PeerRunner(sc, Path(args.peer_bin), args.peer_spp, Path(peer_dir.name), log, args.peer_threads)
        runners.append(peer)
        budgets.append(args.peer_seconds)
        res["peer"] = "indicatrix 0.9.0 (crates.io) through scripts/bench/indicatrix_peer"
        res["peer_white_xyz"] = peer.white_xyz.tolist()
        if args.peer_clear_seconds > 0:
            mat = build_objects(scenes["clear"].objects, file=scenes["clear"].path).materials[0]
            n = np.asarray(mat.n(np.array([400.0, 589.3, 700.0]))).ravel()
            if abs(n[0] - n[2]) > 1e-9:
                raise SystemExit("--peer-clear-seconds needs a clear twin with a constant index")
            runners.append(
                PeerRunner(
                    scenes["clear"],
                    Path(args.peer_bin),
                    args.peer_spp,
                    Path(peer_dir.name) / "clear",
                    log,
                    args.peer_threads,
                    index=float(n[1]),
                    name="indicatrix clear",
                )
            )
            budgets.append(args.peer_clear_seconds)
    run_interleaved(runners, budgets, args.min_passes, args.max_passes, log)

    per_pass = {
        "ours dispersive": r.spp * (r.wavelengths if r.spectral == "stratified" else 1),
        "ours clear": scenes["clear"].render.spp
        * (scenes["clear"].render.wavelengths if scenes["clear"].render.spectral == "stratified" else 1),
        "indicatrix": args.peer_spp,
        "indicatrix clear": args.peer_spp,
    }
    res["renderers"] = {}
    for run in runners:
        ims = np.array(run.ims)
        res["renderers"][run.name] = {
            f"{100 * t:g}%": time_to_target(ims, run.times, per_pass[run.name], t, run.cpu_times)
            for t in TARGETS
        }
    disp = np.array(runners[0].ims)
    res["agreement"] = {
        "clear_vs_dispersive": converged_difference(
            np.array(runners[1].ims), disp, labels=("clear", "dispersive"), quantity="rgb"
        )
    }
    if peer is not None:
        res["agreement"]["dispersive_vs_indicatrix"] = converged_difference(
            disp, np.array(peer.ims), labels=("ours", "indicatrix"), quantity="rgb"
        )
    if len(runners) > 3:
        res["agreement"]["clear_vs_indicatrix_clear"] = converged_difference(
            np.array(runners[1].ims),
            np.array(runners[3].ims),
            labels=("ours_clear", "indicatrix_clear"),
            quantity="rgb",
        )
    # ratios at each target: the peer's time / ours, ours / our clear twin's
    res["ratios"] = {}
    for t in TARGETS:
        key = f"{100 * t:g}%"
        o = res["renderers"]["ours dispersive"][key]
        c = res["renderers"]["ours clear"][key]
        rr = {
            "dispersive_over_clear_wall": o["seconds_to_target"] / c["seconds_to_target"],
            "dispersive_over_clear_cpu": o["cpu_seconds_to_target"] / c["cpu_seconds_to_target"],
        }
        if peer is not None:
            p = res["renderers"]["indicatrix"][key]
            rr["indicatrix_over_dispersive_wall"] = p["seconds_to_target"] / o["seconds_to_target"]
            rr["indicatrix_over_dispersive_cpu"] = p["cpu_seconds_to_target"] / o["cpu_seconds_to_target"]
        res["ratios"][key] = rr

    names = [run.name for run in runners]
    print()
    print(f"| {w}x{h}, linear sRGB | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")

    def row(label, fmt, key="1%"):
        print(f"| {label} | " + " | ".join(fmt(res["renderers"][n][key]) for n in names) + " |")

    row("samples per pixel per pass", lambda c: f"{c['samples_per_pass']:g}")
    row("passes", lambda c: f"{c['passes']}")
    row(
        "wall / CPU seconds per pass",
        lambda c: f"{c['seconds_per_pass']:.2f} / {c['cpu_seconds_per_pass']:.2f}",
    )
    row("rel. RMSE of one pass", lambda c: f"{c['rel_noise_one_pass']:.4f}")
    row(
        "half-split check measured / predicted",
        lambda c: f"{c['half_split_rel_rmse_measured']:.4f} / {c['half_split_rel_rmse_predicted']:.4f}",
    )
    for t in TARGETS:
        key = f"{100 * t:g}%"
        row(
            f"**to {key}: wall / CPU s**",
            lambda c: (
                f"{c['seconds_to_target']:.1f} / {c['cpu_seconds_to_target']:.1f}"
                + (" (one pass)" if c["one_pass_reaches_target"] else "")
            ),
            key,
        )
    print()
    for key, rr in res["ratios"].items():
        print(f"at {key}: " + ", ".join(f"{k} {v:.2f}" for k, v in rr.items()))
    for key, a in res["agreement"].items():
        print(
            f"{key}: converged relative RMSE {100 * a['converged_rel_rmse']:.2f} % (2-sigma upper "
            f"{100 * a['converged_rel_rmse_upper_2sigma']:.2f} %), "
            f"raw {100 * a['raw_rel_rmse_of_means']:.2f} %, "
            f"mean {100 * a['mean_rel_diff']:+.2f} %"
        )
    if args.json:
        from warpoptics.film.image import atomic_path

        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(res, indent=2))
    if args.log:
        from warpoptics.film.image import atomic_path

        with atomic_path(args.log) as tmp:
            Path(tmp).write_text("\n".join(log_lines) + "\n")
    if args.save:
        np.savez_compressed(
            args.save,
            **{n.replace(" ", "_"): np.array(run.ims).mean(0) for n, run in zip(names, runners, strict=True)},
        )
    peer_dir.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
