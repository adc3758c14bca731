"""Gallery sheet of the named gem varieties: 1 ct stones in their usual cuts, face up under the
D65 grading dome and under illuminant A, with the CIELAB L*, C*, h of each stone's pixels.

Every variety of ``warpoptics/materials/datasets/varieties.py`` is cut as listed in :data:`CUTS`
and sized to 1 ct from its density (``warpoptics.grading.carat``), rendered face up under GIA's
grading dome (the 23 deg dark head) with the dome's spectrum D65 and then A
(``warpoptics.grading.appearance.face_up_colour``), and measured: the alpha-weighted mean CIELAB
of the stone's pixels against the light's own white (the observer adapted to the light).  The A
pictures are shown adapted too (Bradford to D65), so each picture shows the colour its numbers
give.  Hues of the varieties with a trade range (``warpoptics/materials/datasets/trade_hues.py``)
are marked in or out of it.

Writes the sheet (PNG) and the numbers (CSV beside it, same name) and prints a Markdown table of
the numbers.  Default 128 x 128 pixels per picture at 16 wavelengths: 54 renders, about 15 min on
one core shared with other work (the birefringent stones are point-sampled, 15-60 s each; the
isotropic ones take beams, 1-3 s).

    python scripts/variety_sheet.py
    python scripts/variety_sheet.py --only ruby,alexandrite --size 64 -o /tmp/sheet.png
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import warpoptics as wo  # noqa: E402
from warpoptics.atomic import atomic_path  # noqa: E402
from warpoptics.grading.appearance import adapted_display, face_up_colour  # noqa: E402
from warpoptics.grading.carat import carat_weight, density_of, size_for_carats  # noqa: E402
from warpoptics.materials.datasets.trade_hues import TRADE_HUES, in_hue_range  # noqa: E402
from warpoptics.materials.datasets.varieties import VARIETIES  # noqa: E402

LIGHTS = ("D65", "A")

# the cuts (proportions as fractions of the width, angles in degrees; the carat sizing scales
# the lengths).  Diamonds: Tolkowsky's round brilliant.  Coloured stones: brilliants with a 37 deg
# crown and a 42 deg pavilion (43 deg below n = 1.7, where a Tolkowsky pavilion leaks light),
# and the step cuts' default tiers.
_DIAMOND = {"shape": "round_brilliant"}
_ROUND = {"shape": "round_brilliant", "crown_angle": 37.0, "pavilion_angle": 42.0}
_OVAL = {"shape": "oval", "length": 1.3, "width": 1.0, "crown_angle": 37.0, "pavilion_angle": 42.0}
_OVAL_LOW = {**_OVAL, "pavilion_angle": 43.0}
_PEAR = {"shape": "pear", "length": 1.5, "width": 1.0, "crown_angle": 37.0, "pavilion_angle": 42.0}
_EMERALD = {"shape": "emerald", "length": 1.4, "width": 1.0}
# tourmaline is cut with the table parallel to c, the length along c (object x)
_ALONG_C = {"optic_axis": [1.0, 0.0, 0.0]}

#: variety -> [[object]] table without size or material (the usual cut of the trade)
CUTS: dict[str, dict] = {
    "ruby": _OVAL,
    "blue_sapphire": _OVAL,
    "yellow_sapphire": _OVAL,
    "padparadscha": _OVAL,
    "emerald": _EMERALD,
    "aquamarine": _EMERALD,
    "morganite": _OVAL_LOW,
    "alexandrite": _OVAL,
    "red_spinel": _OVAL,
    "almandine": _ROUND,
    "rhodolite": _ROUND,
    "spessartine": _ROUND,
    "tsavorite": _ROUND,
    "demantoid": _ROUND,
    "cape_diamond": _DIAMOND,
    "pink_diamond": _DIAMOND,
    "blue_diamond": _DIAMOND,
    "amethyst": _OVAL_LOW,
    "citrine": _EMERALD,
    "peridot": _OVAL,
    "tanzanite": _OVAL,
    "iolite": _OVAL_LOW,
    "rubellite": {**_OVAL, **_ALONG_C},
    "green_tourmaline": {**_EMERALD, **_ALONG_C},
    "paraiba_tourmaline": {**_OVAL, **_ALONG_C},
    "imperial_topaz": _PEAR,
    "blue_zircon": _ROUND,
}


def stone_for(name: str, carats: float = 1.0) -> dict:
    """The [[object]] table of a ``carats`` stone of variety ``name`` in its cut."""
    return size_for_carats({**CUTS.get(name, _ROUND), "material": name}, carats)


def estimator_for(name: str, choice: str) -> str:
    """``choice``, or for ``mixed`` point-sampling for a birefringent variety (the reference
    estimator) and ``auto`` (beams) for an isotropic one."""
    if choice != "mixed":
        return choice
    mat = wo.materials.get(name)
    return "point" if isinstance(mat, (wo.materials.Uniaxial, wo.materials.Biaxial)) else "auto"


def size_text(stone: dict) -> str:
    if "diameter" in stone:
        return f"{stone['diameter']:.2f} mm"
    return f"{stone['length']:.2f} x {stone['width']:.2f} mm"


def verdict(name: str, light: str, h: float) -> str:
    rng = TRADE_HUES.get(name, {}).get(light)
    if rng is None:
        return ""
    return "in" if in_hue_range(h, *rng) else "out"


def _font(size: int):
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow without FreeType
        return ImageFont.load_default()


def compose(rows: list[dict], pictures: dict, size: int, columns: int = 3) -> Image.Image:
    """The sheet: ``columns`` varieties a row, each the D65 and A pictures side by side over the
    name, the cut and L* C* h under each light."""
    gap, pad = 6, 14
    head, foot = 34, 40
    cell_w = 2 * size + gap
    cell_h = head + size + foot
    n = len(rows) // len(LIGHTS)
    nrows = (n + columns - 1) // columns
    title_h = 40
    sheet = Image.new(
        "RGB", (pad + columns * (cell_w + pad), title_h + pad + nrows * (cell_h + pad)), (24, 24, 24)
    )
    draw = ImageDraw.Draw(sheet)
    big, mid, small = _font(15), _font(13), _font(11)
    draw.text(
        (pad, 10),
        "1 ct stones face up under the grading dome: D65 | A (A shown adapted).  "
        "L* C* h of the stone's pixels",
        fill=(235, 235, 235),
        font=big,
    )
    names = list(dict.fromkeys(r["variety"] for r in rows))
    for i, name in enumerate(names):
        x0 = pad + (i % columns) * (cell_w + pad)
        y0 = title_h + pad + (i // columns) * (cell_h + pad)
        first = next(r for r in rows if r["variety"] == name)
        draw.text((x0, y0), name.replace("_", " "), fill=(255, 255, 255), font=big)
        draw.text(
            (x0, y0 + 18),
            f"{first['cut']} {first['size_mm']}, {first['carats']:.2f} ct",
            fill=(170, 170, 170),
            font=small,
        )
        for j, light in enumerate(LIGHTS):
            r = next(r for r in rows if r["variety"] == name and r["light"] == light)
            x = x0 + j * (size + gap)
            sheet.paste(pictures[(name, light)], (x, y0 + head))
            label = light + (f"   trade {r['trade_range']}°" if r["trade_range"] else "")
            draw.text((x, y0 + head + size + 3), label, fill=(170, 170, 170), font=small)
            colour = (235, 235, 235) if r["in_range"] != "out" else (255, 120, 110)
            text = f"L*{r['L']:.0f} C*{r['C']:.0f} h{round(r['h']) % 360}°"
            if r["in_range"]:
                text += f" {r['in_range']}"
            font = mid if draw.textlength(text, font=mid) <= size else small
            draw.text((x, y0 + head + size + 18), text, fill=colour, font=font)
    return sheet


def markdown(rows: list[dict]) -> str:
    out = [
        "| variety | cut (1 ct) | D65 L* | C* | h° | A L* | C* | h° | trade range h° (in/out) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name in dict.fromkeys(r["variety"] for r in rows):
        d, a = (next(r for r in rows if r["variety"] == name and r["light"] == lt) for lt in LIGHTS)
        ranges = []
        for r in (d, a):
            if r["trade_range"]:
                ranges.append(f"{r['light']} {r['trade_range']}: {r['in_range']}")
        out.append(
            f"| {name} | {d['cut']} {d['size_mm']} | {d['L']:.1f} | {d['C']:.1f} | {round(d['h']) % 360} | "
            f"{a['L']:.1f} | {a['C']:.1f} | {round(a['h']) % 360} | {'; '.join(ranges) or '-'} |"
        )
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", default=str(ROOT / "docs/gallery/variety_sheet.png"))
    ap.add_argument("--size", type=int, default=128, help="pixels a side of each picture")
    ap.add_argument("--wavelengths", type=int, default=16)
    ap.add_argument("--carats", type=float, default=1.0)
    ap.add_argument("--only", default="", help="comma-separated varieties (default: all)")
    ap.add_argument("--columns", type=int, default=3)
    ap.add_argument(
        "--estimator",
        default="mixed",
        choices=("mixed", "point", "auto", "beam"),
        help="render.estimator; mixed (default): point for birefringent stones, auto (beams) for the rest",
    )
    args = ap.parse_args(argv)
    names = [n.strip() for n in args.only.split(",") if n.strip()] or list(VARIETIES)
    unknown = [n for n in names if n not in VARIETIES]
    if unknown:
        ap.error(f"unknown varieties {unknown}; known: {', '.join(VARIETIES)}")
    out = Path(args.output)
    rows, pictures = [], {}
    total, k, t_all = len(names) * len(LIGHTS), 0, time.perf_counter()
    for name in names:
        stone = stone_for(name, args.carats)
        ct = carat_weight(stone)
        for light in LIGHTS:
            k += 1
            t = time.perf_counter()
            img, m = face_up_colour(
                stone,
                light,
                size=args.size,
                wavelengths=args.wavelengths,
                render={"estimator": estimator_for(name, args.estimator)},
            )
            rgb = adapted_display(img, light)
            if not np.all(np.isfinite(rgb)) or not all(np.isfinite(m[c]) for c in "LCh"):
                raise SystemExit(f"{name} under {light}: a non-finite colour {m}")
            pictures[(name, light)] = Image.fromarray((np.clip(rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8))
            rng = TRADE_HUES.get(name, {}).get(light)
            row = {
                "variety": name,
                "host": VARIETIES[name]["host"],
                "cut": stone["shape"].replace("_", " "),
                "size_mm": size_text(stone),
                "carats": ct,
                "density_g_cm3": density_of(name),
                "light": light,
                "L": m["L"],
                "a": m["a"],
                "b": m["b"],
                "C": m["C"],
                "h": m["h"],
                "coverage": m["coverage"],
                "trade_range": f"{rng[0]:.0f}-{rng[1]:.0f}" if rng else "",
                "in_range": verdict(name, light, m["h"]),
                "estimator": img.stats.get("estimator", ""),
                "seconds": time.perf_counter() - t,
            }
            rows.append(row)
            print(
                f"[{k:2d}/{total}] {name:19s} {light:3s} {row['cut']:15s} {row['size_mm']:15s} "
                f"L* {m['L']:5.1f}  C* {m['C']:5.1f}  h {m['h']:5.1f}° {row['in_range']:3s} "
                f"({row['estimator']}, {row['seconds']:.1f} s)",
                flush=True,
            )
    sheet = compose(rows, pictures, args.size, args.columns)
    with atomic_path(out, field="-o") as tmp:
        sheet.save(tmp, format="PNG")
    buf = io.StringIO()
    fields = list(rows[0])
    w = csv.DictWriter(buf, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({f: (f"{v:.4g}" if isinstance(v, float) else v) for f, v in r.items()})
    with atomic_path(out.with_suffix(".csv"), field="-o") as tmp:
        Path(tmp).write_text(buf.getvalue())
    print(markdown(rows))
    print(f"wrote {out} and {out.with_suffix('.csv')} ({time.perf_counter() - t_all:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
