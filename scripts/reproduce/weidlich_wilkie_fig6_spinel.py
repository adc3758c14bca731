"""Reproduce Weidlich & Wilkie 2009, fig. 6: a strongly coloured 1 mm spinel brilliant
rendered (a) with and (b) without anomalous dispersion, and (c) their difference image.

The stone is the sweep preset scenes/sweeps/spinel_cobalt.toml (spinel's index from
refractiveindex.info plus three Co2+ absorption bands at 548/580/624 nm); "anomalous" adds the
Kramers–Kronig index of those bands to n (``kramers_kronig = true``), "normal" keeps spinel's
index.  Both renders share their per-pixel camera samples (the renderer's sampling stream does not
depend on the material), so the ΔE00 map shows the material's effect, not noise; (d) is the
noise floor: the normal stone against itself rendered with another seed.

Readout: the largest KK change of n in 400-700 nm, and mean / p95 / max ΔE00 over the stone's
pixels for anomalous vs normal and for the noise floor (printed and written as JSON beside the
PNG).

    python scripts/reproduce/weidlich_wilkie_fig6_spinel.py \
        [-o docs/gallery/weidlich_wilkie_fig6_spinel.png] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import GALLERY, ROOT, Timer, compose, stone_box, sweep_scenes, write_json  # noqa: E402

PRESET = ROOT / "scenes" / "sweeps" / "spinel_cobalt.toml"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "-o", "--output", default=str(GALLERY / "weidlich_wilkie_fig6_spinel.png"), help="PNG to write"
    )
    ap.add_argument("--size", type=int, default=192, help="image width = height (pixels)")
    ap.add_argument("--wavelengths", type=int, default=45, help="stratified wavelengths per pixel")
    ap.add_argument("--scale", type=float, default=5.0, help="ΔE00 at the top of the difference colour map")
    ap.add_argument("--quick", action="store_true", help="tiny images (for tests)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.wavelengths = 32, 9
    if args.size < 8 or args.wavelengths < 1 or not args.scale > 0:
        ap.error("--size must be >= 8, --wavelengths >= 1 and --scale > 0")

    import warpoptics as wo
    from warpoptics import metrics as wm
    from warpoptics.materials import material_from_spec

    with Timer() as total:
        settings = {"width": args.size, "height": args.size, "wavelengths": args.wavelengths}
        jobs = {job.labels["dispersion"]: sc for job, sc in sweep_scenes(PRESET)}
        imgs = {}
        for name in ("normal", "anomalous"):
            with Timer() as t:
                imgs[name] = wo.render(jobs[name], device=args.device, **settings)
            print(f"render {name:9s}: {t.seconds:6.1f} s, {imgs[name].stats['rays'] / 1e6:.1f} M rays")
        noise = wo.render(jobs["normal"], device=args.device, seed=1, **settings)

        lam = np.arange(400.0, 700.5, 1.0)
        n_norm = np.real(material_from_spec(jobs["normal"].objects[0].material).n(lam))
        n_anom = np.real(material_from_spec(jobs["anomalous"].objects[0].material).n(lam))
        dn = n_anom - n_norm
        i_lo, i_hi = int(np.argmin(dn)), int(np.argmax(dn))

        a, b = imgs["anomalous"], imgs["normal"]
        de = wm.delta_e_image(a.xyz, b.xyz)
        st = wm.delta_e_stats(de, a.alpha, b.alpha)
        st["dE_mean_color"] = wm.delta_e_mean_color(a.xyz, a.alpha, b.xyz, b.alpha)
        de_n = wm.delta_e_image(noise.xyz, b.xyz)
        st_n = wm.delta_e_stats(de_n, noise.alpha, b.alpha)
        col = {k: wm.mean_color(v.xyz, v.alpha) for k, v in imgs.items()}

    print(
        f"Kramers–Kronig change of n (400-700 nm): min {dn[i_lo]:+.5f} at {lam[i_lo]:.0f} nm, "
        f"max {dn[i_hi]:+.5f} at {lam[i_hi]:.0f} nm"
    )
    for k, c in col.items():
        print(f"mean colour {k:9s}: L* {c['L']:.2f} a* {c['a']:.2f} b* {c['b']:.2f}")
    print(
        f"ΔE00 anomalous vs normal : mean {st['dE_mean']:.3f}  p95 {st['dE_p95']:.3f}  "
        f"max {st['dE_max']:.2f}  "
        f"(mean colours {st['dE_mean_color']:.3f})"
    )
    print(
        f"ΔE00 noise floor (seed 1): mean {st_n['dE_mean']:.3f}  p95 {st_n['dE_p95']:.3f}  "
        f"max {st_n['dE_max']:.2f}"
    )
    print(f"total time {total.seconds:.1f} s")

    box = stone_box(a.alpha, b.alpha)  # panels cropped to the stone (display only)
    rows = [
        [
            a.display()[box],
            b.display()[box],
            wm.difference_image(de[box], scale=args.scale),
            wm.difference_image(de_n[box], scale=args.scale),
        ]
    ]
    titles = [
        [
            "(a) anomalous (Kramers–Kronig)",
            "(b) normal dispersion",
            f"(c) ΔE00 a vs b: mean {st['dE_mean']:.2f}, p95 {st['dE_p95']:.2f}",
            f"(d) noise floor: b vs seed 1, mean {st_n['dE_mean']:.2f}",
        ]
    ]
    compose(
        args.output,
        rows,
        titles,
        suptitle="Weidlich & Wilkie 2009 fig. 6: 1 mm cobalt spinel, "
        f"{args.wavelengths} stratified wavelengths, {args.size}² px",
        colorbar={"row": 0, "scale": args.scale, "label": "ΔE00"},
    )
    out = Path(args.output)
    write_json(
        out.with_suffix(".json"),
        {
            "size_px": args.size,
            "wavelengths": args.wavelengths,
            "dn_min": float(dn[i_lo]),
            "dn_min_nm": float(lam[i_lo]),
            "dn_max": float(dn[i_hi]),
            "dn_max_nm": float(lam[i_hi]),
            "anomalous_vs_normal": st,
            "noise_floor": st_n,
            "mean_color": col,
            "seconds": total.seconds,
        },
    )
    print(f"wrote {out} and {out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
