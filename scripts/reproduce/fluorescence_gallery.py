"""Fluorescence and colour change: renders of scenes/fluorescence/ with their numbers.

Writes ``docs/gallery/fluorescence_diamond.png`` (a round brilliant with no N3 centre, medium
and very strong N3 fluorescence, and the very strong stone without its fluorescence
(quantum_yield = 0), in daylight (D65), shade (D75) and under a 365 nm lamp),
``fluorescence_cube.png`` (a uranium-glass cube under a UV365 LED panel),
``fluorescence_colour_change.png`` (alexandrite and the colour-change garnet in daylight, D65,
and incandescent light, A) and ``fluorescence.json`` with every number printed on them: the
stones' mean CIELAB colour (``warpoptics.metrics.mean_color``; each light's own white for the
colour-change pair), CIEDE2000 and chroma differences, the emission's share of the UV render
and the colour change (hue-angle difference and CIEDE2000 between the two lights).

The diamonds are traced with one path tree per wavelength (``spectral_bundle=False``, as every
fluorescent render is): the re-emission draws from its own random stream, so a fluorescent
stone and the same stone without fluorescence share their camera trees and their difference is
the emission alone, without noise from the rest of the picture.

    python scripts/reproduce/fluorescence_gallery.py              # 96 x 96 panels (minutes)
    python scripts/reproduce/fluorescence_gallery.py --size 160
    python scripts/reproduce/fluorescence_gallery.py --quick      # tiny, for the tests
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import GALLERY, ROOT, Timer, compose, stone_box, write_json  # noqa: E402

SCENES = ROOT / "scenes" / "fluorescence"
STRENGTH = {"medium": 1.0, "very_strong": 8.0}  # x the library's N3 concentration
LIGHTS = {
    "daylight": ("diamond_daylight.toml", {}),
    "shade": ("diamond_daylight.toml", {"light.0.spectrum": "D75"}),
    "uv365": ("diamond_uv365.toml", {}),
}
VARIANTS = {
    "none": {"object.0.material": "diamond"},
    "medium": {"object.0.material.fluorescence.strength": STRENGTH["medium"]},
    "medium_off": {
        "object.0.material.fluorescence.strength": STRENGTH["medium"],
        "object.0.material.fluorescence.quantum_yield": 0.0,
    },
    "very_strong": {"object.0.material.fluorescence.strength": STRENGTH["very_strong"]},
    "very_strong_off": {
        "object.0.material.fluorescence.strength": STRENGTH["very_strong"],
        "object.0.material.fluorescence.quantum_yield": 0.0,
    },
}
SHOWN = ("none", "medium", "very_strong", "very_strong_off")


def _render(file: Path, overrides: dict, size: int, render: dict, *, bundle: bool | None = False):
    from warpoptics.pipelines.render import Renderer
    from warpoptics.scene import Scene

    sc = Scene.load(file).with_overrides(overrides, width=size, height=size, **render)
    return Renderer(sc, spectral_bundle=bundle).run()


def _colour(img, white=None) -> dict:
    from warpoptics import metrics

    m = metrics.mean_color(img.xyz, img.alpha, white_xyz=white)
    return {k: round(float(v), 5) for k, v in m.items()}


def _white(spectrum: str) -> np.ndarray:
    """XYZ (Y = 1) of a white diffuser lit by ``spectrum``: the white of CIELAB under that light."""
    from warpoptics.spectra import grid, light_spectrum, spectrum_to_xyz

    g = grid()
    w = spectrum_to_xyz(g, light_spectrum(spectrum, g))
    return w / w[1]


def diamonds(size: int, render: dict, out: Path) -> dict:
    from warpoptics import metrics

    imgs, res = {}, {}
    for light, (file, light_over) in LIGHTS.items():
        for name, over in VARIANTS.items():
            with Timer() as t:
                imgs[light, name] = _render(SCENES / file, {**light_over, **over}, size, render)
            res.setdefault(light, {})[name] = {**_colour(imgs[light, name]), "seconds": round(t.seconds, 1)}
            print(f"diamond {light:8s} {name:16s} {res[light][name]}")
        for s in ("medium", "very_strong"):
            on, off = imgs[light, s], imgs[light, s + "_off"]
            r = res[light]
            r[f"{s}_vs_off"] = {
                "delta_e00": round(metrics.delta_e_mean_color(on.xyz, on.alpha, off.xyz, off.alpha), 4),
                "delta_chroma": round(r[s]["C"] - r[s + "_off"]["C"], 4),
                "delta_b": round(r[s]["b"] - r[s + "_off"]["b"], 4),
                "delta_XYZ": [round(r[s][k] - r[s + "_off"][k], 6) for k in "XYZ"],
                "emission_share_Y": round(1.0 - r[s + "_off"]["Y"] / r[s]["Y"], 5) if r[s]["Y"] > 0 else 0.0,
            }
    box = stone_box(*(imgs[k].alpha for k in imgs))
    rows, titles = [], []
    for light in LIGHTS:
        rows.append([imgs[light, n].display()[box] for n in SHOWN])
        t = []
        for n in SHOWN:
            c = res[light][n]
            label = f"{light} · {n.replace('_', ' ')}\nL {c['L']:.1f} C {c['C']:.2f} h {c['h']:.0f}°"
            if n == "very_strong":
                label += f"\nΔE00 {res[light]['very_strong_vs_off']['delta_e00']:.2f} vs off"
            t.append(label)
        titles.append(t)
    compose(
        out / "fluorescence_diamond.png",
        rows,
        titles,
        suptitle="Diamond with N3 fluorescence: none / medium / very strong / very strong with yield 0",
        footer="UV365 row: exposure +3; mean colours of the stone (CIELAB, D65 white)",
    )
    return res


def cube(size: int, render: dict, out: Path) -> dict:
    with Timer() as t:
        img = _render(SCENES / "cube_uv_spot.toml", {}, size, render, bundle=None)
        img_off = _render(
            SCENES / "cube_uv_spot.toml",
            {"object.0.material": {"base": "uranium_glass", "fluorescence": {"quantum_yield": 0.0}}},
            size,
            render,
            bundle=None,
        )
    c, c_off = _colour(img), _colour(img_off)
    res = {"glow": c, "yield_0": c_off, "seconds": round(t.seconds, 1)}
    print(f"cube {res}")
    compose(
        out / "fluorescence_cube.png",
        [[img.display(), img_off.display()]],
        [[f"uranium glass, UV365 panel\nY {c['Y']:.4f}", f"yield 0\nY {c_off['Y']:.2g}"]],
        suptitle="Fluorescent cube under a 365 nm LED panel",
        panel_inches=2.6,
    )
    return res


def colour_change(size: int, render: dict, out: Path) -> dict:
    import colour

    res, rows, titles = {}, [], []
    for stone in ("alexandrite", "colour_change_garnet"):
        row, t, labs = [], [], []
        for light in ("D65", "A"):
            with Timer() as tm:
                img = _render(
                    SCENES / f"{stone}.toml", {"light.0.spectrum": light}, size, render, bundle=None
                )
            c = _colour(img, white=_white(light))
            labs.append(np.array([c["L"], c["a"], c["b"]]))
            res.setdefault(stone, {})[light] = {**c, "seconds": round(tm.seconds, 1)}
            row.append(img.display())
            t.append(f"{stone.replace('_', ' ')} · {light}\nL {c['L']:.1f} C {c['C']:.1f} h {c['h']:.0f}°")
            print(f"{stone} {light} {res[stone][light]}")
        dh = abs(res[stone]["D65"]["h"] - res[stone]["A"]["h"]) % 360.0
        res[stone]["delta_hue"] = round(min(dh, 360.0 - dh), 3)
        res[stone]["delta_e00"] = round(float(colour.delta_E(labs[0], labs[1], method="CIE 2000")), 4)
        t[1] += f"\nΔh {res[stone]['delta_hue']:.0f}°, ΔE00 {res[stone]['delta_e00']:.1f}"
        rows.append(row)
        titles.append(t)
    compose(
        out / "fluorescence_colour_change.png",
        rows,
        titles,
        suptitle="Colour change: daylight (D65) vs incandescent (A), CIELAB against each light's white",
    )
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=96, help="panel width and height (<= 160)")
    ap.add_argument("--quick", action="store_true", help="24-pixel panels, one sample: a smoke run")
    ap.add_argument("--out-dir", default=str(GALLERY))
    args = ap.parse_args(argv)
    size = 24 if args.quick else min(int(args.size), 160)
    render = {"spp": 1, "wavelengths": 8} if args.quick else {}
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with Timer() as t:
        data = {
            "size": size,
            "render": render,
            "diamond": diamonds(size, render, out),
            "cube": cube(size, render, out),
            "colour_change": colour_change(size, render, out),
        }
    data["seconds"] = round(t.seconds, 1)
    write_json(out / "fluorescence.json", data)
    print(f"wrote {out}/fluorescence_*.png and fluorescence.json in {t.seconds:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
