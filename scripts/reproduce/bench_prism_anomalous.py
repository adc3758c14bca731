"""Optical bench after Weidlich & Wilkie 2009 §4, fig. 3 and 5: prisms of BK7, water
and three rose bengal solutions lit by a white beam at the thin edge, traced forward onto a wall.

For each material the beam runs 7 um below the apex (thin edge, about 5 um of liquid) and then
0.5 mm below it (toward the thick edge).  Readout per material: the position u of each
wavelength's spot on the wall (power-weighted centroid of the light transmitted straight
through, mm; right = more deviation) for the wavelengths that get through (>= 0.1 % of their
power), whether u(lambda) is monotonic, the number of reversals of the colour order, the fan-out
(range of u), the transmitted power and luminous fraction, and at the thick edge the power left
in the dye's band (470-590 nm) relative to the thin edge (the pattern fades).

    python scripts/reproduce/bench_prism_anomalous.py -o docs/gallery/prism.png \
        [--json docs/gallery/prism.json]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "bench" / "prism.toml"
MATERIALS = ("bk7", "water", "rose_bengal_10", "rose_bengal_3.3", "rose_bengal_1")
APEX_Z = 0.9396926  # apex height of the scene's prism (mm)
THIN, THICK = 0.007, 0.5  # beam depth below the apex (mm)


def readout(result, *, min_fraction: float = 1.0e-3) -> dict:
    """Spot positions of the directly transmitted light (two interfaces) and their order."""
    sp = result.spot_positions(0, depth=2)
    ok = sp["power"] >= min_fraction * result.weights * result.ledger["emitted"]
    wl, u = sp["wavelength"][ok], sp["u"][ok]
    du = np.diff(u)
    signs = np.sign(du[np.abs(du) > 1e-6])
    reversals = int(np.count_nonzero(signs[1:] != signs[:-1])) if signs.size > 1 else 0
    band = (sp["wavelength"] >= 470) & (sp["wavelength"] <= 590)
    y = sum(float(s.xyz[..., 1].sum()) for s in result.screens)
    return {
        "wavelength": wl,
        "u": u,
        "monotonic": reversals == 0,
        "reversals": reversals,
        "fan_out": float(u.max() - u.min()) if u.size else 0.0,
        "transmitted": float(sp["power"].sum()),
        "band_power": float(sp["power"][band].sum()),
        "luminous": y,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG figure to write")
    ap.add_argument("--wavelengths", type=int, default=96, help="spectral samples")
    ap.add_argument("--rays", type=int, default=8, help="beam positions")
    ap.add_argument("--json", default=None, help="also write the readout as JSON here")
    ap.add_argument("--quick", action="store_true", help="24 wavelengths, 2 beam positions (for tests)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.wavelengths, args.rays = 24, 2

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.pipelines.bench import bench
    from warpoptics.scene.bench import BenchScene

    scene = BenchScene.load(SCENE)
    rows = {}
    strips = {}
    print(
        f"{'material':16s} {'edge':5s} {'monotonic':9s} {'reversals':9s} {'fan-out mm':10s} "
        f"{'T power':8s} {'Y':7s} {'band 470-590':12s}"
    )
    for mat in MATERIALS:
        for edge, depth in (("thin", THIN), ("thick", THICK)):
            r = bench(
                scene,
                device=args.device,
                overrides={
                    "object.0.material": mat,
                    "source.position": [-5.0, 0.0, APEX_Z - depth],
                    "render.wavelengths": args.wavelengths,
                    "source.rays": args.rays,
                },
            )
            ro = readout(r)
            rows[(mat, edge)] = ro
            strips[(mat, edge)] = r.screens[0].as_image().display()
            lg = r.ledger
            closure = (lg["screen"] + lg["absorbed"] + lg["escaped"]) / lg["emitted"]
            print(
                f"{mat:16s} {edge:5s} {str(ro['monotonic']):9s} {ro['reversals']:9d} {ro['fan_out']:10.3f} "
                f"{ro['transmitted']:8.4f} {ro['luminous']:7.4f} {ro['band_power']:12.3e}  "
                f"(ledger closure {closure:.6f})"
            )
    for mat in MATERIALS:
        thin, thick = rows[(mat, "thin")], rows[(mat, "thick")]
        ratio = thick["band_power"] / thin["band_power"] if thin["band_power"] > 0 else float("nan")
        print(
            f"fade {mat:16s}: band power thick/thin = {ratio:.3e}, luminous thick/thin = "
            f"{thick['luminous'] / thin['luminous']:.3f}"
        )
    wider = rows[("rose_bengal_10", "thin")]["fan_out"] / rows[("water", "thin")]["fan_out"]
    print(f"fan-out rose bengal 10 % / water = {wider:.2f}")
    if args.json:
        import json

        from warpoptics.film.image import atomic_path

        summary = {
            f"{mat}/{edge}": {k: v for k, v in ro.items() if k not in ("wavelength", "u")}
            for (mat, edge), ro in rows.items()
        }
        summary["fan_out_ratio_rose_bengal_10_vs_water"] = wider
        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")

    fig = plt.figure(figsize=(12, 9))
    gs = fig.add_gridspec(len(MATERIALS) + 1, 2, height_ratios=[1] * len(MATERIALS) + [5])
    for i, mat in enumerate(MATERIALS):
        for j, edge in enumerate(("thin", "thick")):
            a = fig.add_subplot(gs[i, j])
            img = strips[(mat, edge)]
            # the beam is 4 um tall: show the lit rows, stretched
            lit = np.nonzero(img.max(axis=(1, 2)) > 0)[0]
            rows_ = img[lit.min() : lit.max() + 1] if lit.size else img
            a.imshow(np.repeat(rows_, 8, axis=0), aspect="auto", extent=(-30, 30, 0, 1))
            a.set_yticks([])
            a.set_title(f"{mat}, {edge} edge", fontsize=8)
            if i < len(MATERIALS) - 1:
                a.set_xticks([])
    a = fig.add_subplot(gs[-1, :])
    for mat, col in zip(MATERIALS, ("k", "tab:blue", "#8b0045", "#d6417f", "#f4a3c4"), strict=True):
        ro = rows[(mat, "thin")]
        a.plot(ro["wavelength"], ro["u"], ".-", color=col, label=mat)
    a.set_xlabel("wavelength (nm)")
    a.set_ylabel("spot position on the wall u (mm), right = more deviated")
    a.grid(alpha=0.3)
    a.legend(fontsize=8)
    fig.suptitle(
        "Forward-traced prism experiment (Weidlich & Wilkie 2009 §4, fig. 5): thin edge vs thick edge"
    )
    fig.tight_layout()
    from warpoptics.film.image import save_figure

    save_figure(fig, args.output, dpi=100)  # atomic: temp file + rename
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
