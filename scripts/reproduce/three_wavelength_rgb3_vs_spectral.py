"""Reproduce "An experiment in three-wavelength dispersive ray tracing of diamonds": the three-IOR ``rgb3``
render beside the spectral render at EQUAL render time, each measured against a converged
spectral reference.

Scene: scenes/diamond.toml (a 6.5 mm Tolkowsky round brilliant under studio soft boxes, the
seed's "light boxes").  ``rgb3`` traces three wavelengths per sample, 700 / 546.1 / 435.8 nm (diamond
n = 2.406 / 2.424 / 2.450 there, close to the seed's 2.40 / 2.43 / 2.46), so the spectrum a facet
disperses becomes three separate coloured copies: banding.  The spectral render uses 45 stratified
wavelengths at 1 spp; its render time (the render loop, excluding scene set-up, identical for
both) is measured, and ``rgb3`` gets the spp that fill the same time (its time per spp measured
at 1 spp first).

Reference: stratified 45 wavelengths at ``--ref-spp`` spp, rendered as two independent halves
(seeds 101 and 102) and averaged; its own noise is RMSE(half a, half b) / 2 (each half carries
variance s^2, their mean s^2 / 2, and RMSE(a - b) estimates sqrt(2) s).

A second copy of each equal-time render (seed 1) splits its error: noise = RMSE(copy 1, copy 2)
/ sqrt(2), bias = sqrt(RMSE^2 - noise^2 - reference noise^2): rgb3's error is bias (banding and
a tint that no amount of time removes), the spectral render's is noise (it shrinks with time).

Readout: each render's time, and its RMSE against the reference over display-encoded sRGB
([0, 1], all channels of the stone's pixels; the JSON also has it over all pixels, where rgb3's
tinted surround counts) and its mean CIEDE2000 over the stone's pixels (printed and written as
JSON beside the PNG).

    python scripts/reproduce/three_wavelength_rgb3_vs_spectral.py \
        [-o docs/gallery/three_wavelength_rgb3_vs_spectral.png] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import FIGURE_SAMPLING, GALLERY, ROOT, Timer, compose, display_rmse, write_json  # noqa: E402

SCENE = ROOT / "scenes" / "diamond.toml"


def _timed(base, device, repeats: int, settings: dict):
    """(1-spp render at seed 0, the least render seconds of ``repeats`` such renders)."""
    import warpoptics as wo

    img = wo.render(base, device=device, spp=1, seed=0, **settings)
    seconds = img.stats["seconds"]
    for _ in range(repeats - 1):
        seconds = min(seconds, wo.render(base, device=device, spp=1, seed=0, **settings).stats["seconds"])
    return img, seconds


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "-o", "--output", default=str(GALLERY / "three_wavelength_rgb3_vs_spectral.png"), help="PNG to write"
    )
    ap.add_argument("--size", type=int, default=128, help="image width = height (pixels)")
    ap.add_argument(
        "--wavelengths", type=int, default=45, help="stratified wavelengths of the spectral render"
    )
    ap.add_argument("--ref-spp", type=int, default=8, help="spp of the reference (even: two halves)")
    ap.add_argument("--quick", action="store_true", help="tiny images (for tests)")
    ap.add_argument(
        "--rgb3-spp",
        type=int,
        default=None,
        help="fix rgb3's spp instead of measuring the equal-time spp (for tests: a --quick render "
        "takes milliseconds, whose ratio a loaded machine does not keep)",
    )
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.wavelengths, args.ref_spp = 32, 15, 4
    if args.size < 8 or args.wavelengths < 3 or args.ref_spp < 2 or args.ref_spp % 2:
        ap.error("--size must be >= 8, --wavelengths >= 3 and --ref-spp an even number >= 2")
    if args.rgb3_spp is not None and args.rgb3_spp < 1:
        ap.error(f"--rgb3-spp must be >= 1, got {args.rgb3_spp}")

    import warpoptics as wo
    from warpoptics import metrics as wm

    # the scene's camera narrowed (fov 15 -> 10.5 degrees) so that the stone fills the frame
    fixed = {"camera.fov": 10.5, **FIGURE_SAMPLING}  # the sampling the figure was made with
    base = wo.Scene.load(SCENE).with_overrides(fixed, width=args.size, height=args.size)
    spectral = {"spectral": "stratified", "wavelengths": args.wavelengths}
    rgb3 = {"spectral": "rgb3", "wavelengths": 3}
    diamond = wo.materials.get("diamond")
    n_rgb = np.real(diamond.n(np.asarray(wo.spectra.RGB3_WAVELENGTHS)))

    # a --quick render takes milliseconds, which a busy machine can double: there the time of a
    # 1-spp render is the least of three identical ones (same seed, same image), so that the
    # equal-time spp does not depend on the load
    repeats = 3 if args.quick else 1
    with Timer() as total:
        spec, t_spec = _timed(base, args.device, repeats, spectral)
        probe, t_probe = _timed(base, args.device, repeats, rgb3)
        spp_eq = args.rgb3_spp or max(1, int(round(t_spec / t_probe)))
        fast = wo.render(base, device=args.device, spp=spp_eq, seed=0, **rgb3)
        # second independent copies: noise = RMSE(copy 1, copy 2) / sqrt(2)
        spec2 = wo.render(base, device=args.device, spp=1, seed=1, **spectral)
        fast2 = wo.render(base, device=args.device, spp=spp_eq, seed=1, **rgb3)
        half = args.ref_spp // 2
        ref_a = wo.render(base, device=args.device, spp=half, seed=101, **spectral)
        ref_b = wo.render(base, device=args.device, spp=half, seed=102, **spectral)

    ref_xyz = 0.5 * (ref_a.xyz + ref_b.xyz)
    ref_alpha = 0.5 * (ref_a.alpha + ref_b.alpha)
    ref = replace(ref_a, xyz=ref_xyz, alpha=ref_alpha, stokes=0.5 * (ref_a.stokes + ref_b.stokes))
    ref_d = ref.display()
    stone = ref_alpha > 0.0  # RMSE over the stone's pixels (rgb3 also tints the surround; see the JSON)
    ref_noise = display_rmse(ref_a.display(), ref_b.display(), stone) / 2.0
    ref_noise_de = float(
        wm.delta_e_stats(wm.delta_e_image(ref_a.xyz, ref_b.xyz), ref_a.alpha, ref_b.alpha)["dE_mean"]
    )

    res = {}
    for name, img in (("rgb3", fast), ("rgb3_1spp", probe), ("spectral", spec)):
        de = wm.delta_e_stats(wm.delta_e_image(img.xyz, ref_xyz), img.alpha, ref_alpha)
        res[name] = {
            "spp": int(img.stats.get("spp", 0)) or None,
            "seconds": img.stats["seconds"],
            "rmse_display": display_rmse(img.display(), ref_d, stone),
            "rmse_display_all_pixels": display_rmse(img.display(), ref_d),
            "dE_mean": de["dE_mean"],
            "dE_p95": de["dE_p95"],
        }
    res["rgb3"]["spp"], res["rgb3_1spp"]["spp"], res["spectral"]["spp"] = spp_eq, 1, 1
    # error split: RMSE^2 = bias^2 + noise^2 + (reference noise)^2
    for name, (i1, i2) in (("spectral", (spec, spec2)), ("rgb3", (fast, fast2))):
        r = res[name]
        r["noise_display"] = display_rmse(i1.display(), i2.display(), stone) / np.sqrt(2.0)
        r["bias_display"] = float(
            np.sqrt(max(r["rmse_display"] ** 2 - r["noise_display"] ** 2 - ref_noise**2, 0.0))
        )

    print(
        f"diamond n at the rgb3 wavelengths {wo.spectra.RGB3_WAVELENGTHS} nm: "
        + " / ".join(f"{v:.4f}" for v in n_rgb)
        + "  (the three-wavelength paper: 2.40 / 2.43 / 2.46)"
    )
    print(
        f"reference: {args.wavelengths} stratified wavelengths x {args.ref_spp} spp "
        f"({ref_a.stats['seconds'] + ref_b.stats['seconds']:.1f} s); its own noise: RMSE {ref_noise:.4f}, "
        f"halves differ by mean ΔE00 {ref_noise_de:.2f}"
    )
    print(
        f"{'render':28s} {'spp':>4s} {'time s':>7s} {'RMSE vs ref':>11s} {'noise':>6s} {'bias':>6s} "
        f"{'ΔE00 mean':>9s} {'ΔE00 p95':>8s}"
    )
    labels = {
        "spectral": f"spectral ({args.wavelengths} stratified)",
        "rgb3": "rgb3, fixed spp" if args.rgb3_spp else "rgb3, equal time",
        "rgb3_1spp": "rgb3, 1 spp",
    }
    for k in ("spectral", "rgb3", "rgb3_1spp"):
        r = res[k]
        nb = (
            f"{r['noise_display']:6.4f} {r['bias_display']:6.4f}"
            if "bias_display" in r
            else f"{'':6s} {'':6s}"
        )
        print(
            f"{labels[k]:28s} {r['spp']:4d} {r['seconds']:7.2f} {r['rmse_display']:11.4f} {nb} "
            f"{r['dE_mean']:9.2f} {r['dE_p95']:8.2f}"
        )
    print(f"total time {total.seconds:.1f} s")

    # the stone's middle, enlarged: where the fire is (and rgb3's bands)
    h = args.size
    y0, y1, x0, x1 = int(0.30 * h), int(0.62 * h), int(0.30 * h), int(0.70 * h)

    def crop(img):
        c = img[y0:y1, x0:x1]
        return np.repeat(np.repeat(c, 2, axis=0), 2, axis=1)

    fd, sd = fast.display(), spec.display()
    rows = [[fd, sd, ref_d], [crop(fd), crop(sd), crop(ref_d)]]
    titles = [
        [
            f"rgb3 (three IORs), {spp_eq} spp, {res['rgb3']['seconds']:.1f} s",
            f"spectral, {args.wavelengths} wl x 1 spp, {t_spec:.1f} s",
            f"reference, {args.wavelengths} wl x {args.ref_spp} spp",
        ],
        [
            *(
                f"RMSE {res[k]['rmse_display']:.3f} (bias {res[k]['bias_display']:.3f}), "
                f"ΔE {res[k]['dE_mean']:.1f}"
                for k in ("rgb3", "spectral")
            ),
            f"own noise: RMSE {ref_noise:.4f}",
        ],
    ]
    compose(
        args.output,
        rows,
        titles,
        panel_inches=2.4,
        suptitle=f"Three wavelengths (rgb3) vs spectral diamond at equal render time, {args.size}² px",
    )
    out = Path(args.output)
    write_json(
        out.with_suffix(".json"),
        {
            "size_px": args.size,
            "wavelengths": args.wavelengths,
            "ref_spp": args.ref_spp,
            "n_rgb3": [float(v) for v in n_rgb],
            "ref_noise_rmse_display": ref_noise,
            "ref_noise_dE_mean": ref_noise_de,
            "renders": res,
            "seconds": total.seconds,
        },
    )
    print(f"wrote {out} and {out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
