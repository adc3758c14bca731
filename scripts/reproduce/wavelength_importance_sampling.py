"""Reproduce "Spectral dispersion with Sellmeier and wavelength importance sampling": uniform random
wavelengths vs wavelengths importance-sampled by the CIE curves, at EQUAL sample counts, with the
measured noise of each.

Scene: scenes/diamond.toml (a dispersive 6.5 mm diamond under studio soft boxes whose light is
D65 times the sRGB basis spectra).  Each pixel gets ``--samples`` random wavelengths (and camera
rays) per render: ``uniform`` draws them with pdf 1 / 470 nm over 360-830 nm, ``importance`` with
pdf proportional to xbar + ybar + zbar (``warpoptics.spectra``).  Both estimators are unbiased;
they differ only in noise.  Each strategy is rendered with ``--seeds`` independent seeds; the
noise is the per-pixel standard deviation over those seeds (sample std, ddof = 1), of the linear
XYZ (relative to the image's mean Y) and of the display-encoded sRGB, RMS over the stone's
pixels and all channels; and of the XYZ of the surround (pixels no sample's primary ray hit the
stone: a smooth spectrum, no geometric noise, the wavelength noise alone).  (uniform / importance
noise)^2 is how many times more samples uniform needs for the same noise.  The stone's mean XYZ
over all seeds, with its standard error over the seeds, checks that both are unbiased (seed
003's uniform image came out darker from its normalisation; ours must not).

    python scripts/reproduce/wavelength_importance_sampling.py \
        [-o docs/gallery/wavelength_importance_sampling.png] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import FIGURE_SAMPLING, GALLERY, ROOT, Timer, compose, write_json  # noqa: E402

SCENE = ROOT / "scenes" / "diamond.toml"
STRATEGIES = ("uniform", "importance")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "-o", "--output", default=str(GALLERY / "wavelength_importance_sampling.png"), help="PNG to write"
    )
    ap.add_argument("--size", type=int, default=128, help="image width = height (pixels)")
    ap.add_argument("--samples", type=int, default=8, help="random wavelengths (camera samples) per pixel")
    ap.add_argument("--seeds", type=int, default=6, help="independent renders per strategy (>= 2)")
    ap.add_argument("--quick", action="store_true", help="tiny images (for tests)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.seeds = 32, 4
    if args.size < 8 or args.samples < 1 or args.seeds < 2:
        ap.error("--size must be >= 8, --samples >= 1 and --seeds >= 2")

    import warpoptics as wo
    from warpoptics import metrics as wm

    # the scene's camera narrowed (fov 15 -> 10.5 degrees) so that the stone fills the frame
    fixed = {"camera.fov": 10.5, **FIGURE_SAMPLING}  # the sampling the figure was made with
    base = wo.Scene.load(SCENE).with_overrides(fixed, width=args.size, height=args.size, spp=1)
    runs: dict[str, list] = {s: [] for s in STRATEGIES}
    with Timer() as total:
        for s in STRATEGIES:
            for k in range(args.seeds):
                runs[s].append(
                    wo.render(
                        base,
                        device=args.device,
                        spectral=s,
                        wavelengths=args.samples,
                        seed=1000 + k,
                        bundle=False,  # the paper compares per-wavelength estimators (no spectral bundles)
                    )
                )

    alpha = np.mean([im.alpha for s in STRATEGIES for im in runs[s]], axis=0)
    stone = alpha >= 0.5
    bg = alpha == 0.0
    res = {}
    sigma_maps = {}
    for s in STRATEGIES:
        xyz = np.stack([im.xyz for im in runs[s]])
        disp = np.stack([im.display() for im in runs[s]])
        y_mean = float(xyz[..., 1].mean(axis=0)[stone].mean())
        sd_xyz = xyz.std(axis=0, ddof=1)
        sd_disp = disp.std(axis=0, ddof=1)
        sigma_maps[s] = np.sqrt((sd_disp**2).mean(axis=-1))
        # each seed's stone-mean XYZ: their spread over seeds is the standard error of the mean
        per_seed = np.array([(im.xyz[stone]).mean(axis=0) for im in runs[s]])
        se = per_seed.std(axis=0, ddof=1) / np.sqrt(len(per_seed))
        res[s] = {
            "stone_mean_Y": y_mean,
            "stone_mean_xyz": per_seed.mean(axis=0).tolist(),
            "stone_mean_xyz_se": se.tolist(),
            "noise_xyz_rel": float(np.sqrt((sd_xyz[stone] ** 2).mean()) / y_mean),
            "noise_display": float(np.sqrt((sd_disp[stone] ** 2).mean())),
            "noise_display_all_pixels": float(np.sqrt((sd_disp**2).mean())),
            # the surround (no stone in any sample): a smooth spectrum, pure wavelength noise
            "noise_xyz_rel_surround": float(
                np.sqrt((sd_xyz[bg] ** 2).mean()) / xyz[..., 1].mean(axis=0)[bg].mean()
            )
            if bg.any()
            else float("nan"),
            "seconds_per_render": float(np.mean([im.stats["seconds"] for im in runs[s]])),
            "mean_color": wm.mean_color(xyz.mean(axis=0), alpha),
        }
    ratio = res["uniform"]["noise_display"] / res["importance"]["noise_display"]
    ratio_xyz = res["uniform"]["noise_xyz_rel"] / res["importance"]["noise_xyz_rel"]
    ratio_bg = res["uniform"]["noise_xyz_rel_surround"] / res["importance"]["noise_xyz_rel_surround"]
    de_bias = wm.delta_e_mean_color(
        np.mean([im.xyz for im in runs["uniform"]], axis=0),
        alpha,
        np.mean([im.xyz for im in runs["importance"]], axis=0),
        alpha,
    )

    print(f"{args.samples} random wavelengths per pixel, {args.seeds} seeds per strategy, {args.size}² px")
    print(
        f"{'strategy':11s} {'stone mean Y':>12s} {'noise XYZ/Y':>11s} {'noise sRGB':>10s} {'all px':>7s} "
        f"{'surround XYZ/Y':>14s} {'s/render':>8s}"
    )
    for s in STRATEGIES:
        r = res[s]
        print(
            f"{s:11s} {r['stone_mean_Y']:12.4f} {r['noise_xyz_rel']:11.4f} {r['noise_display']:10.4f} "
            f"{r['noise_display_all_pixels']:7.4f} {r['noise_xyz_rel_surround']:14.4f} "
            f"{r['seconds_per_render']:8.2f}"
        )
    print(
        f"noise ratio uniform / importance: {ratio:.2f} (display sRGB), {ratio_xyz:.2f} (XYZ); "
        f"{ratio_bg:.2f} (XYZ of the surround: wavelength noise alone); "
        f"uniform needs {ratio**2:.1f}x the samples for the same display noise"
    )
    for s in STRATEGIES:
        m, e = res[s]["stone_mean_xyz"], res[s]["stone_mean_xyz_se"]
        print(
            f"stone mean XYZ {s:10s}: "
            + ", ".join(f"{v:.4f} ± {d:.4f}" for v, d in zip(m, e, strict=True))
            + " (± standard error over the seeds)"
        )
    dz = np.abs(np.subtract(res["uniform"]["stone_mean_xyz"], res["importance"]["stone_mean_xyz"]))
    sez = np.hypot(res["uniform"]["stone_mean_xyz_se"], res["importance"]["stone_mean_xyz_se"])
    print(
        f"mean colours of the two (all seeds) differ by ΔE00 {de_bias:.3f}; XYZ differences are "
        + ", ".join(f"{d / e:.1f}" for d, e in zip(dz, sez, strict=True))
        + " standard errors (both unbiased)"
    )
    print(f"total time {total.seconds:.1f} s")

    top = float(np.percentile(sigma_maps["uniform"][stone], 95)) if stone.any() else 0.1
    top = top if top > 0 else 0.1
    rows = [
        [runs["uniform"][0].display(), runs["importance"][0].display()],
        [
            wm.difference_image(sigma_maps["uniform"], scale=top, colormap="viridis"),
            wm.difference_image(sigma_maps["importance"], scale=top, colormap="viridis"),
        ],
    ]
    titles = [
        [
            f"uniform, {args.samples} wavelengths/pixel",
            f"importance (CIE xyz), {args.samples} wavelengths/pixel",
        ],
        [
            f"per-pixel σ over {args.seeds} seeds: {res['uniform']['noise_display']:.4f}",
            f"per-pixel σ: {res['importance']['noise_display']:.4f} (÷{ratio:.2f})",
        ],
    ]
    compose(
        args.output,
        rows,
        titles,
        panel_inches=2.2,
        suptitle="Wavelength importance sampling: uniform vs importance wavelengths, equal samples",
        colorbar={"row": 1, "scale": top, "label": "σ (display sRGB)", "cmap": "viridis"},
    )
    out = Path(args.output)
    write_json(
        out.with_suffix(".json"),
        {
            "size_px": args.size,
            "samples_per_pixel": args.samples,
            "seeds": args.seeds,
            "strategies": res,
            "noise_ratio_display": ratio,
            "noise_ratio_xyz": ratio_xyz,
            "noise_ratio_xyz_surround": ratio_bg,
            "mean_color_dE": de_bias,
            "mean_xyz_difference_in_standard_errors": (dz / sez).tolist(),
            "seconds": total.seconds,
        },
    )
    print(f"wrote {out} and {out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
