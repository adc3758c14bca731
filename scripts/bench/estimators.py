"""Point samples against pixel beams on every shipped scene that holds a stone: seconds to 2 % and 1 %.

For each scene (default: every camera scene under ``scenes/`` with a solid, plus
``scenes/ruby_step.toml`` and ``scenes/emerald_cut.toml``) at ``--res`` pixels a side:

1. a long **point-sampled** reference: two independent renders of ``--ref-spp`` samples per pixel
   (``render.estimator = "point"``), whose difference gives the reference's own noise;
2. passes of the two estimators alternating (point, beam, point, beam, ...; each pass a new seed),
   until each has spent ``--seconds`` of render time or reached 1 %;
3. after every pass, the relative RMSE of the running mean of linear sRGB against the reference,
   the reference's noise removed in quadrature (so a beam's bias stays in its error), against
   the wall (render) and process CPU seconds spent so far.

``--crop N`` renders only the centred N x N window of the ``--res`` image (the camera's field
narrowed, every pixel's footprint unchanged): the same per-pixel work and noise as the full
image's centre, at a fraction of the references' cost; ``--aim X,Y,Z`` turns the camera to look
at that point first (a window on one stone of several).  Beams run wherever they apply by name,
also where ``auto`` keeps point samples (the ``auto`` column says which it takes).

Where a target is not reached, the seconds to it are extrapolated from the last pass as
error ~ 1/sqrt(time) and marked so.  Where beams do not apply to a scene, the row says why
(``Image.stats["estimator_reason"]``).  Writes ``--json`` and prints a table.

    python scripts/bench/estimators.py --res 512 --ref-spp 256 --seconds 120 \
        --json scripts/bench/results/estimators_512.json

Run it alone on the machine: it measures seconds.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import warpoptics as wo  # noqa: E402
from warpoptics.atomic import atomic_path  # noqa: E402
from warpoptics.errors import InputError  # noqa: E402
from warpoptics.pipelines.render import Renderer  # noqa: E402

EXTRA = ("ruby_step.toml", "emerald_cut.toml")
TARGETS = (0.02, 0.01)


def stone_scenes() -> list[Path]:
    """Camera scenes under scenes/ that hold at least one solid (bench, microscope and sweep files
    are not camera scenes and are skipped by loading them)."""
    out = []
    for p in sorted((ROOT / "scenes").rglob("*.toml")):
        if p.parent.name in ("sweeps", "microscope", "bench"):
            continue
        try:
            sc = wo.Scene.load(p)
        except (InputError, ValueError, TypeError):
            continue
        if getattr(sc, "objects", None):
            out.append(p)
    for name in EXTRA:
        if ROOT / "scenes" / name not in out:
            out.append(ROOT / "scenes" / name)
    return out


def render(sc, estimator: str, seed: int, spp: int | None = None) -> tuple[np.ndarray, float, float, dict]:
    """(linear sRGB, render seconds, process CPU seconds, stats) of one pass."""
    over: dict = {"render.estimator": estimator, "render.seed": seed}
    if spp is not None:
        over["render.spp"] = spp
        over["render.adaptive"] = False
    r = Renderer(sc.with_overrides(over))
    r.load_kernels()
    c0 = time.process_time()
    img = r.run()
    return img.rgb.astype(np.float64), float(img.stats["seconds"]), time.process_time() - c0, img.stats


def rel_error(img: np.ndarray, ref: np.ndarray, mean: float, ref_noise: float) -> float:
    raw = float(np.sqrt(np.mean((img - ref) ** 2)) / mean)
    return math.sqrt(max(raw**2 - ref_noise**2, 0.0))


def seconds_to(history: list[tuple[float, float, float]], target: float) -> dict:
    """Wall and CPU seconds at which the running error first reaches ``target``; else extrapolated
    from the last pass as error ~ 1/sqrt(time)."""
    for err, wall, cpu in history:
        if err <= target:
            return {"wall": wall, "cpu": cpu, "extrapolated": False}
    err, wall, cpu = history[-1]
    f = (err / target) ** 2 if err > 0 else 1.0
    return {"wall": wall * f, "cpu": cpu * f, "extrapolated": True}


def cropped(sc, res: int, crop: int | None):
    """``sc`` at ``res`` pixels a side, or its centred ``crop`` x ``crop`` window at the same
    pixel footprint (a pinhole's field or an orthographic view narrowed by crop / res)."""
    if not crop or crop >= res:
        return sc.with_overrides(None, width=res, height=res)
    f = crop / res
    cam = sc.camera
    over: dict = {"camera.view_height": cam.view_height * f}
    if cam.type != "orthographic":
        over["camera.fov"] = math.degrees(2.0 * math.atan(math.tan(math.radians(cam.fov) / 2.0) * f))
    return sc.with_overrides(over, width=crop, height=crop)


def beams_apply(sc) -> bool:
    """Whether pixel beams can trace ``sc`` when asked for by name (auto may still pick points)."""
    try:
        Renderer(sc.with_overrides({"render.estimator": "beam", "render.seed": 0}))
    except InputError:
        return False
    return True


def measure(path: Path, a) -> dict:
    sc = wo.Scene.load(path)
    if a.aim:
        sc = sc.with_overrides({"camera.look_at": [float(v) for v in a.aim.split(",")]})
    sc = cropped(sc, a.res, a.crop)
    row: dict = {"scene": str(path.relative_to(ROOT)), "res": a.res, "crop": a.crop, "aim": a.aim}
    probe = Renderer(sc.with_overrides({"render.estimator": "auto", "render.seed": 0}))
    row["auto"] = probe.estimator
    row["auto_reason"] = probe.estimator_reason
    del probe
    ref = []
    for seed in (900001, 900002):
        img, sec, cpu, _ = render(sc, "point", seed, spp=a.ref_spp)
        ref.append(img)
    mean = float(0.5 * (ref[0] + ref[1]).mean())
    ref_noise = float(np.sqrt(np.mean((ref[0] - ref[1]) ** 2)) / mean) / 2.0
    reference = 0.5 * (ref[0] + ref[1])
    row["reference"] = {"spp": a.ref_spp, "noise": ref_noise}
    by_name = row["auto"] == "beam" or beams_apply(sc)
    estimators = ["point"] + (["beam"] if by_name else [])
    if not by_name:
        row["beam"] = {"applies": False, "why": row["auto_reason"]}
    acc = {e: None for e in estimators}
    n = {e: 0 for e in estimators}
    hist: dict[str, list] = {e: [] for e in estimators}
    spent = {e: [0.0, 0.0] for e in estimators}
    seed = 1
    while True:
        active = [e for e in estimators if spent[e][0] < a.seconds and (not hist[e] or hist[e][-1][0] > 0.01)]
        if not active or seed > a.max_passes:
            break
        for e in active:  # alternate: one pass of each
            img, sec, cpu, _ = render(sc, e, seed)
            acc[e] = img if acc[e] is None else acc[e] + img
            n[e] += 1
            spent[e][0] += sec
            spent[e][1] += cpu
            err = rel_error(acc[e] / n[e], reference, mean, ref_noise)
            hist[e].append((err, spent[e][0], spent[e][1]))
            print(f"  {path.name} {e} pass {n[e]}: {err * 100:.2f} % after {spent[e][0]:.1f} s", flush=True)
        seed += 1
    for e in estimators:
        row[e] = {
            "passes": n[e],
            "error": hist[e][-1][0],
            "wall": spent[e][0],
            "cpu": spent[e][1],
            **{f"to_{int(t * 100)}pct": seconds_to(hist[e], t) for t in TARGETS},
        }
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=512)
    ap.add_argument("--ref-spp", type=int, default=256, help="point samples per pixel of each reference half")
    ap.add_argument("--seconds", type=float, default=120.0, help="render seconds per estimator and scene")
    ap.add_argument("--max-passes", type=int, default=64)
    ap.add_argument("--crop", type=int, help="render only the centred N x N window of the --res image")
    ap.add_argument("--scenes", nargs="*", help="scene files (default: every shipped scene with a stone)")
    ap.add_argument(
        "--aim", help="X,Y,Z: turn the camera to look at this point (mm), so that --crop's window is on it"
    )
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    paths = [Path(p).resolve() for p in a.scenes] if a.scenes else stone_scenes()
    rows = []
    for p in paths:
        print(f"{p.relative_to(ROOT)}:", flush=True)
        rows.append(measure(p, a))
        if a.json:  # after every scene, atomically: a long run keeps what it finished
            with atomic_path(a.json) as tmp, open(tmp, "w") as f:
                json.dump({"rows": rows, "argv": sys.argv[1:]}, f, indent=1)
    print(f"\n{'scene':34s} {'auto':6s} {'point s to 2 %':>16s} {'beam s to 2 %':>15s} {'ratio':>7s}")
    for r in rows:
        pt = r["point"]["to_2pct"]
        bm = r.get("beam", {}).get("to_2pct")
        mark = lambda d: "~" if d["extrapolated"] else " "  # noqa: E731
        beam_s = f"{mark(bm)}{bm['wall']:14.1f}" if bm else f"{'n/a':>15s}"
        ratio = f"{pt['wall'] / bm['wall']:7.1f}" if bm else f"{'':7s}"
        print(f"{r['scene']:34s} {r['auto']:6s} {mark(pt)}{pt['wall']:15.1f} {beam_s} {ratio}")
        if not bm:
            print(f"{'':34s} beams: {r['beam']['why']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
