"""Reproduce Weidlich & Wilkie 2009, fig. 7: a pink brilliant at 10, 1, 0.1 and 0.01 mm,
absorbance scaled by 10 mm / size so all four look alike, with normal dispersion (top row), with
the anomalous dispersion of its absorption band (Kramers–Kronig, middle row) and their ΔE00
difference images (bottom row).

The jobs are those of the sweep preset scenes/sweeps/gem_sizes.toml (resolved by the sweep
machinery, as ``warpoptics sweep`` does; see the preset for how size is rendered: the complex
index is the small stone's, the transport length the 10 mm stone's), rendered smaller.  Paired
renders share their camera samples, so a ΔE map shows the material's effect; each size's noise
floor is the normal stone against itself with another seed.

Readout per size: the peak absorption (1/mm), the largest Kramers–Kronig change of n, and
ΔE00 mean / p95 / max over the stone's pixels (anomalous vs normal) beside the noise floor's mean
(printed as a table and written as JSON beside the PNG).

    python scripts/reproduce/weidlich_wilkie_fig7_gem_sizes.py \
        [-o docs/gallery/weidlich_wilkie_fig7_gem_sizes.png] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import GALLERY, ROOT, Timer, compose, stone_box, sweep_scenes, write_json  # noqa: E402

PRESET = ROOT / "scenes" / "sweeps" / "gem_sizes.toml"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "-o", "--output", default=str(GALLERY / "weidlich_wilkie_fig7_gem_sizes.png"), help="PNG to write"
    )
    ap.add_argument("--size", type=int, default=128, help="image width = height (pixels)")
    ap.add_argument("--wavelengths", type=int, default=45, help="stratified wavelengths per pixel")
    ap.add_argument("--scale", type=float, default=10.0, help="ΔE00 at the top of the difference colour map")
    ap.add_argument("--quick", action="store_true", help="tiny images (for tests)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.wavelengths = 24, 9
    if args.size < 8 or args.wavelengths < 1 or not args.scale > 0:
        ap.error("--size must be >= 8, --wavelengths >= 1 and --scale > 0")

    import warpoptics as wo
    from warpoptics import metrics as wm
    from warpoptics.materials import material_from_spec

    settings = {"width": args.size, "height": args.size, "wavelengths": args.wavelengths}
    lam = np.arange(400.0, 700.5, 1.0)
    with Timer() as total:
        scenes = {}
        for job, sc in sweep_scenes(PRESET):
            scenes[(job.values["size_mm"], job.labels["dispersion"])] = sc
        sizes = sorted({s for s, _ in scenes}, reverse=True)
        table = []
        panels = {"normal": [], "anomalous": [], "diff": []}
        for s in sizes:
            norm, anom = scenes[(s, "normal")], scenes[(s, "anomalous")]
            with Timer() as t:
                a = wo.render(anom, device=args.device, **settings)
                b = wo.render(norm, device=args.device, **settings)
                c = wo.render(norm, device=args.device, seed=1, **settings)
            de = wm.delta_e_image(a.xyz, b.xyz)
            st = wm.delta_e_stats(de, a.alpha, b.alpha)
            st_n = wm.delta_e_stats(wm.delta_e_image(c.xyz, b.xyz), c.alpha, b.alpha)
            spec_a = anom.objects[0].material
            dn = np.real(material_from_spec(spec_a).n(lam)) - np.real(
                material_from_spec(norm.objects[0].material).n(lam)
            )
            row = {
                "size_mm": s,
                "peak_alpha_per_mm": float(spec_a["bands"][0]["peak_alpha_per_mm"]),
                "dn_max_abs": float(np.abs(dn).max()),
                "dE_mean": st["dE_mean"],
                "dE_p95": st["dE_p95"],
                "dE_max": st["dE_max"],
                "dE_mean_color": wm.delta_e_mean_color(a.xyz, a.alpha, b.xyz, b.alpha),
                "noise_dE_mean": st_n["dE_mean"],
                "noise_dE_p95": st_n["dE_p95"],
                "seconds": t.seconds,
            }
            table.append(row)
            box = stone_box(a.alpha, b.alpha)  # panels cropped to the stone (display only)
            panels["normal"].append((b.display()[box], f"{s:g} mm, normal"))
            panels["anomalous"].append((a.display()[box], f"{s:g} mm, anomalous (KK)"))
            panels["diff"].append(
                (
                    wm.difference_image(de[box], scale=args.scale),
                    f"ΔE00 mean {st['dE_mean']:.2f}, p95 {st['dE_p95']:.1f}",
                )
            )

    print(
        f"{'size mm':>8s} {'alpha /mm':>9s} {'max|dn|':>8s} {'dE mean':>8s} {'dE p95':>7s} {'dE max':>7s} "
        f"{'dE colour':>9s} {'noise mean':>10s} {'noise p95':>9s} {'time s':>6s}"
    )
    for r in table:
        print(
            f"{r['size_mm']:8g} {r['peak_alpha_per_mm']:9.4g} {r['dn_max_abs']:8.1e} {r['dE_mean']:8.3f} "
            f"{r['dE_p95']:7.2f} {r['dE_max']:7.1f} {r['dE_mean_color']:9.3f} {r['noise_dE_mean']:10.3f} "
            f"{r['noise_dE_p95']:9.2f} {r['seconds']:6.1f}"
        )
    print(f"total time {total.seconds:.1f} s")

    rows = [[p for p, _ in panels[k]] for k in ("normal", "anomalous", "diff")]
    titles = [[t for _, t in panels[k]] for k in ("normal", "anomalous", "diff")]
    compose(
        args.output,
        rows,
        titles,
        panel_inches=1.8,
        suptitle=f"Weidlich & Wilkie 2009 fig. 7: pink brilliant, absorbance × 10 mm / size; "
        f"{args.wavelengths} stratified wavelengths, {args.size}² px",
        colorbar={"row": 2, "scale": args.scale, "label": "ΔE00"},
    )
    out = Path(args.output)
    write_json(
        out.with_suffix(".json"),
        {"size_px": args.size, "wavelengths": args.wavelengths, "sizes": table, "seconds": total.seconds},
    )
    print(f"wrote {out} and {out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
