"""Pixel beams against point sampling: the bias of ``render.estimator = "beam"`` (stages/pixel_beam.py).

Renders the fire benchmark scene (scenes/bench_fire.toml: dispersive, clear, polarized diamond
under the lat-long studio map) with its perspective camera and with an orthographic one of the
same view, each (a) by point sampling (the unbiased estimator: spectral bundles at R2 pixel
positions) as a long reference in two independent halves, and (b) by pixel beams in two
independent renders.  Reports, in linear sRGB over the whole image: each estimator's own noise
(half against half), and the beam image against the reference, with the part of that difference
the two noises explain removed (sqrt(max(0, d^2 - n_ref^2 - n_beam^2))): what is left is bias.
An orthographic beam is exact (no bias expected); a perspective one takes a pixel's rays
parallel (its bias is what this measures).

    python scripts/bench/beam_bias.py --res 96 --ref-spp 256 --json scripts/bench/results/beam_bias_96.json
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from warpoptics.color import xyz_to_srgb_linear
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene

ROOT = Path(__file__).resolve().parents[2]


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(((a - b) ** 2).mean()) / b.mean())


def render(scene: Scene, **kw) -> tuple[np.ndarray, float]:
    r = Renderer(scene.with_overrides(None, **kw))
    t = time.process_time()
    im = r.run()
    return xyz_to_srgb_linear(im.xyz), time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "bench_fire.toml"))
    ap.add_argument("--res", type=int, default=96)
    ap.add_argument("--ref-spp", type=int, default=256, help="point samples per pixel of each reference half")
    ap.add_argument("--ref-wavelengths", type=int, default=64)
    ap.add_argument("--beam-wavelengths", type=int, default=128)
    ap.add_argument("--beam-split", type=float, default=0.01, help="the beams' split_threshold (roulette)")
    ap.add_argument("--cameras", nargs="+", default=["perspective", "orthographic"])
    ap.add_argument(
        "--ref-cache", default=None, help="keep the references in this .npz (reused when it matches)"
    )
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    base = Scene.load(a.scene)
    out = {
        "scene": a.scene,
        "res": a.res,
        "ref_spp": a.ref_spp,
        "ref_wavelengths": a.ref_wavelengths,
        "beam_wavelengths": a.beam_wavelengths,
        "beam_split": a.beam_split,
        "rows": [],
    }
    for cam in a.cameras:
        sc = base
        if cam == "orthographic":
            # the same view: the orthographic height that the perspective fov gives at look_at
            c = base.camera
            dist = float(np.linalg.norm(np.subtract(c.position, c.look_at)))
            vh = 2.0 * dist * np.tan(np.radians(c.fov) / 2.0)
            sc = base.with_overrides({"camera.type": "orthographic", "camera.view_height": vh})
        common = dict(width=a.res, height=a.res, adaptive=False, split_threshold=0.01)
        ref, t_ref = [], 0.0
        key = f"{Path(a.scene).name}_{cam}_{a.res}_{a.ref_spp}_{a.ref_wavelengths}"
        cache = Path(a.ref_cache) if a.ref_cache else None
        stored = dict(np.load(cache)) if cache and cache.exists() else {}
        if key in stored:
            ref = list(stored[key])
        else:
            for seed in (1, 2):
                img, t = render(
                    sc,
                    seed=seed,
                    spp=a.ref_spp,
                    wavelengths=a.ref_wavelengths,
                    bundle_lanes=16,
                    estimator="point",
                    **common,
                )
                ref.append(img)
                t_ref += t
            if cache:
                from warpoptics.film.image import atomic_path

                stored[key] = np.stack(ref)
                with atomic_path(cache) as tmp:
                    with open(tmp, "wb") as fh:
                        np.savez(fh, **stored)
        beam, t_beam = [], 0.0
        for seed in (3, 4):
            img, t = render(
                sc,
                seed=seed,
                spp=1,
                wavelengths=a.beam_wavelengths,
                bundle_lanes=16,
                estimator="beam",
                **{**common, "split_threshold": a.beam_split},
            )
            beam.append(img)
            t_beam += t
        n_ref = rel(ref[0], ref[1]) / 2.0  # noise of the mean of the two halves
        n_beam = rel(beam[0], beam[1]) / 2.0
        d = rel(0.5 * (beam[0] + beam[1]), 0.5 * (ref[0] + ref[1]))
        bias = float(np.sqrt(max(0.0, d**2 - n_ref**2 - n_beam**2)))
        mean_ratio = float((beam[0] + beam[1]).mean() / (ref[0] + ref[1]).mean())
        row = {
            "camera": cam,
            "ref_noise": n_ref,
            "beam_noise": n_beam,
            "beam_vs_ref": d,
            "bias_estimate": bias,
            "mean_ratio": mean_ratio,
            "ref_cpu_s": t_ref,
            "beam_cpu_s": t_beam,
        }
        out["rows"].append(row)
        print(
            f"{cam:12s} {a.res}x{a.res}: reference (2 x {a.ref_spp} spp, {a.ref_wavelengths} wl) "
            f"noise {100 * n_ref:.2f} % "
            f"[{t_ref:.0f} CPU-s]; beams (2 x 1 spp, {a.beam_wavelengths} wl) noise {100 * n_beam:.2f} % "
            f"[{t_beam:.0f} CPU-s]; beams vs reference {100 * d:.2f} % rel. RMSE, "
            f"less the noises: {100 * bias:.2f} %; mean ratio {mean_ratio:.4f}",
            flush=True,
        )
    if a.json:
        from warpoptics.film.image import atomic_path

        with atomic_path(a.json) as tmp:
            Path(tmp).write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
