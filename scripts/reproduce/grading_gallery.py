"""The grading looks of a Tolkowsky, GIA's reference and a deep-pavilion brilliant (warpoptics.grading).

The stones (6.5 mm round brilliant diamonds): a Tolkowsky (table 53 %, crown 34.5°, pavilion
40.75°), GIA's reference proportions (57 %, 34.0°, 40.7°) and a deliberately poor, deep stone
(55 %, 34.5°, 43°).  Per stone, into ``OUT/grading/<stone>_<look>.png``:

- ``aset`` — ASET (AGS zones: blue = the observer's obstruction, 10°; red = light from 45-90°
  above the girdle plane; green = 0-45°; white = leakage), :func:`warpoptics.grading.aset`: the
  energy share of each zone and the area share of the pixels it dominates, for the stone, its
  centre (r < 0.3 girdle radii) and the crown (outside the table);
- ``idealscope`` — Ideal Scope (red reflector, 5° hole; leakage white);
- ``arrows`` / ``hearts`` — the Hearts & Arrows viewer face-up and face-down (30° dark cone),
  with the dark lobes counted on rings of the image (:func:`~warpoptics.grading.count_pattern`:
  8 hearts/arrows when 8 lobes is the count on two thirds of the rings, else the pattern is
  reported broken) and the 8-fold asymmetry (:func:`~warpoptics.grading.rotational_asymmetry`);
- ``brightness_map`` — the classified brightness/contrast map of the face-up view under ISO light
  with the 10° head (:func:`~warpoptics.grading.brightness_map`: bright >= 0.5, dark < 0.15 of
  the dome's white);
- ``tilt_strip`` — the tilt series 0-30° in 5° steps about azimuth 0 (across a pavilion main)
  through the sweep runner (:func:`warpoptics.sweep.grading.tilt_series_sweep`): ISO views on top,
  the spot-lit (fire) views below, light return and fire under each frame;
- ``lp_map`` — the light-performance map: the protocol's light return (ISO, 10° head, the
  observer at 250 mm) as a function of the tilt direction (angle) and tilt (radius, 0-20°).
  Rendered at azimuths 0-22.5° in 5.625° steps; the rest of the circle follows from the
  brilliant's exact 8-fold mirror symmetry (a tilt at azimuth a looks like one at -a and a + 45°).

Composites (``OUT/grading_looks.png``: one row per stone, the scopes and maps;
``OUT/grading_tilt_strips.png``) and ``OUT/grading_gallery.json`` (every number above, the
renders and seconds spent) are written atomically; the tilt sweeps run in a temporary folder
(``--work`` keeps them, resumable).

    python scripts/reproduce/grading_gallery.py -o docs/gallery           # 256 px scopes
    python scripts/reproduce/grading_gallery.py --quick -o /tmp/gallery   # seconds (the Tolkowsky)
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from warpoptics.color import encode_srgb
from warpoptics.film.image import save_figure, write_png
from warpoptics.grading.performance import PROTOCOL, brightness_map, tilted_light_return, windowing
from warpoptics.grading.presets import face_up_scene
from warpoptics.grading.scopes import (
    aset,
    count_pattern,
    hearts_and_arrows,
    ideal_scope,
    rotational_asymmetry,
)
from warpoptics.sweep.grading import tilt_series_sweep, write_tilt_series
from warpoptics.sweep.results import write_text_atomic
from warpoptics.sweep.runner import SweepRunner

STONES = {
    "tolkowsky": ("Tolkowsky 53/34.5/40.75", {"table": 0.53, "crown_angle": 34.5, "pavilion_angle": 40.75}),
    "gia_reference": (
        "GIA reference 57/34.0/40.7",
        {"table": 0.57, "crown_angle": 34.0, "pavilion_angle": 40.7},
    ),
    "deep43": ("deep pavilion 55/34.5/43", {"table": 0.55, "crown_angle": 34.5, "pavilion_angle": 43.0}),
}
LOOKS = ("aset", "idealscope", "arrows", "hearts", "brightness_map", "lp_map")


def _lobes(img, face_down):
    """The hearts/arrows count (None when the pattern is broken), its verdict and the dark-lobe
    count per ring (as `warpoptics grade hearts`)."""
    lc = count_pattern(img, face_down=face_down)
    return lc.count, lc.verdict, list(lc.per_ring)


def _fold(psi):
    """A tilt direction (degrees) mapped onto 0-22.5° by the brilliant's 8-fold mirror symmetry."""
    p = np.mod(psi, 45.0)
    return np.where(p > 22.5, 45.0 - p, p)


def _gray(img):
    return np.repeat(np.clip(img, 0.0, 1.0)[..., None], 3, axis=-1)


def _tilt_strip(stone, proto, tilts, work: Path):
    """Tilt series at azimuth 0 through the sweep runner: (strip (H, W, 3) uint8, rows, renders)."""
    from PIL import Image as PILImage
    from PIL import ImageDraw

    sweep = tilt_series_sweep(stone, tilts=tilts, azimuths=(0.0,), protocol=proto)
    runner = SweepRunner(sweep, work, resume=True, progress=False)
    res = runner.run()
    write_tilt_series(runner, res)
    by_tilt = {float(j.values["tilt"]): j for j in res.jobs}
    rows = {float(r["tilt"]): r for r in res.rows}
    scale = max(1, 96 // proto.size)
    w = h = proto.size * scale
    bar = 12
    strip = PILImage.new("RGB", (w * len(tilts), 2 * h + 2 * bar), (0, 0, 0))
    draw = ImageDraw.Draw(strip)
    table = []
    for k, t in enumerate(tilts):
        job, r = by_tilt[float(t)], rows[float(t)]
        for v, view in enumerate(("iso", "spots")):
            tile = PILImage.open(runner.image_path(job, view, "png")).convert("RGB")
            strip.paste(tile.resize((w, h), PILImage.Resampling.NEAREST), (k * w, v * (h + bar)))
        lr, fire = float(r["iso_light_return"]), float(r["spots_fire"])
        draw.text((k * w + 2, h), f"{t:g} deg LR {lr:.2f}", fill=(230, 230, 230))
        draw.text((k * w + 2, 2 * h + bar), f"fire {fire:.3f}", fill=(230, 230, 230))
        table.append(
            {
                "tilt": float(t),
                **{m: float(r[f"iso_{m}"]) for m in ("light_return", "contrast", "extinction")},
                **{m: float(r[f"spots_{m}"]) for m in ("fire", "scintillation")},
            }
        )
    return np.asarray(strip), table, 3 * len(tilts)


def _lp_map(stone, proto):
    """Light return over tilt directions (module docstring): (table, per-view rows, renders)."""
    res = tilted_light_return(stone, proto)
    table = {(float(t), float(a)): lr for t, a, lr, _c, _e in res["per_view"]}
    rows = [{"tilt": t, "azimuth": a, "light_return": lr, "contrast": c, "extinction": e}
            for t, a, lr, c, e in res["per_view"]]  # fmt: skip
    return table, rows, res["renders"]


def _plot_lp_map(ax, table, tilts, azimuths):
    psi = np.arange(0.0, 360.0 + 1e-9, azimuths[1] - azimuths[0])
    folded = _fold(psi)
    grid = np.array(
        [[table[(0.0, azimuths[0])] if t == 0 else table[(t, float(a))] for a in folded] for t in tilts]
    )
    th, rr = np.meshgrid(np.radians(psi), np.asarray(tilts, dtype=float))
    mesh = ax.pcolormesh(th, rr, grid, shading="gouraud", cmap="viridis")
    ax.set_ylim(0, max(tilts))
    ax.set_yticks([t for t in tilts if t > 0])
    ax.set_yticklabels([f"{t:g}°" for t in tilts if t > 0], fontsize=6, color="w")
    ax.set_xticks(np.radians(np.arange(0, 360, 45)))
    ax.set_xticklabels([])
    return mesh


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="docs/gallery", help="output folder")
    ap.add_argument("--size", type=int, default=256, help="scope and map views, px (<= 256)")
    ap.add_argument("--stones", default=",".join(STONES), help="of " + ", ".join(STONES))
    ap.add_argument("--work", default=None, help="keep the tilt sweeps here (resumable)")
    ap.add_argument("--quick", action="store_true", help="the Tolkowsky only, 24 px, two tilts, coarse map")
    args = ap.parse_args(argv)
    size = 24 if args.quick else args.size
    stones = "tolkowsky" if args.quick and args.stones == ",".join(STONES) else args.stones
    names = [s.strip() for s in stones.split(",") if s.strip()]
    unknown = [s for s in names if s not in STONES]
    if unknown:
        ap.error(f"unknown stone {unknown[0]!r} (of {', '.join(STONES)})")
    out = Path(args.output)
    looks_dir = out / "grading"
    strip_proto = dataclasses.replace(
        PROTOCOL, size=12 if args.quick else 96, wavelengths=2 if args.quick else 8
    )
    strip_tilts = (0.0, 10.0) if args.quick else tuple(float(t) for t in range(0, 31, 5))
    map_azimuths = (0.0, 22.5) if args.quick else tuple(5.625 * k for k in range(5))
    map_proto = dataclasses.replace(
        PROTOCOL,
        tilts=(0.0, 10.0) if args.quick else (0.0, 5.0, 10.0, 15.0, 20.0),
        azimuths=map_azimuths,
        size=12 if args.quick else 64,
        wavelengths=2 if args.quick else 8,
    )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    titles = [
        "ASET",
        "Ideal Scope",
        "arrows (face-up)",
        "hearts (face-down)",
        "brightness map",
        "light return vs tilt",
    ]
    fig = plt.figure(figsize=(2.0 * len(LOOKS), 2.25 * len(names)))
    strips = []
    settings = {
        "scope_size": size,
        "strip_protocol": dataclasses.asdict(strip_proto),
        "strip_tilts": list(strip_tilts),
        "map_protocol": dataclasses.asdict(map_proto),
    }
    readout: dict = {"settings": settings, "stones": {}}
    with tempfile.TemporaryDirectory(prefix="warpoptics-gallery-") as tmp:
        work = Path(args.work) if args.work else Path(tmp)
        for row, key in enumerate(names):
            label, kw = STONES[key]
            stone = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", **kw}
            t0 = time.perf_counter()
            a_img, zones, a_bands = aset(stone, size=size)
            i_img, ifr, i_bands = ideal_scope(stone, size=size)
            arrows, ar_b = hearts_and_arrows(stone, size=size)
            hearts, he_b = hearts_and_arrows(stone, size=size, face_down=True)
            n_arrows, arrows_verdict, arrow_rings = _lobes(arrows, False)
            n_hearts, hearts_verdict, heart_rings = _lobes(hearts, True)
            from warpoptics.pipelines.render import render
            from warpoptics.scene.load import Scene

            face = render(
                Scene.from_dict(face_up_scene(stone, size=size, wavelengths=4 if args.quick else 16))
            )
            b_img, b_fr, _rel = brightness_map(face.xyz, face.alpha)
            table, lp_rows, lp_renders = _lp_map(stone, map_proto)
            strip, strip_rows, strip_renders = _tilt_strip(stone, strip_proto, strip_tilts, work / key)
            renders = a_bands.renders + i_bands.renders + ar_b.renders + he_b.renders + 1
            renders += lp_renders + strip_renders
            seconds = time.perf_counter() - t0
            images = {
                "aset": encode_srgb(a_img),
                "idealscope": encode_srgb(i_img),
                "arrows": _gray(arrows),
                "hearts": _gray(hearts),
                "brightness_map": encode_srgb(b_img),
            }
            for look, img in images.items():
                write_png(looks_dir / f"{key}_{look}.png", img)
            write_png(looks_dir / f"{key}_tilt_strip.png", strip)
            strips.append((label, strip))
            lr_mean = float(np.mean([r["light_return"] for r in lp_rows]))
            readout["stones"][key] = {
                "label": label,
                "stone": stone,
                "aset": zones,
                "ideal_scope": ifr,
                "windowing": windowing(a_bands),
                "arrows": n_arrows,
                "arrows_verdict": arrows_verdict,
                "arrows_per_ring": arrow_rings,
                "hearts": n_hearts,
                "hearts_verdict": hearts_verdict,
                "hearts_per_ring": heart_rings,
                "asymmetry_arrows": rotational_asymmetry(arrows),
                "asymmetry_hearts": rotational_asymmetry(hearts),
                "brightness_map": b_fr,
                "tilt_series": strip_rows,
                "lp_map": lp_rows,
                "lp_map_mean_light_return": lr_mean,
                "renders": renders,
                "seconds": round(seconds, 1),
            }
            captions = [
                f"leak {zones['leak']:.2f} (crown {zones['leak_crown']:.2f}), red {zones['red']:.2f}",
                f"leak {ifr['leak']:.2f}",
                f"{n_arrows} arrows" if n_arrows is not None else "arrows: pattern broken",
                f"{n_hearts} hearts" if n_hearts is not None else "hearts: pattern broken",
                f"bright {b_fr['bright']:.2f}, dark {b_fr['dark']:.2f}",
                f"mean {lr_mean:.3f}",
            ]
            for col, look in enumerate(LOOKS):
                polar = look == "lp_map"
                ax = fig.add_subplot(len(names), len(LOOKS), row * len(LOOKS) + col + 1, polar=polar)
                if polar:
                    mesh = _plot_lp_map(ax, table, list(map_proto.tilts), map_azimuths)
                    fig.colorbar(mesh, ax=ax, fraction=0.046, pad=0.08).ax.tick_params(labelsize=6)
                    ax.set_xlabel(captions[col], fontsize=7)
                else:
                    ax.imshow(images[look], interpolation="nearest")
                    ax.set_xticks([])
                    ax.set_yticks([])
                    ax.set_xlabel(captions[col], fontsize=7)
                if row == 0:
                    ax.set_title(titles[col], fontsize=8)
                if col == 0:
                    ax.set_ylabel(label, fontsize=8)
            # the light-performance map of this stone on its own
            f2, a2 = plt.subplots(subplot_kw={"polar": True}, figsize=(3.2, 3.0))
            mesh = _plot_lp_map(a2, table, list(map_proto.tilts), map_azimuths)
            f2.colorbar(mesh, ax=a2, fraction=0.046, pad=0.1, label="light return")
            a2.set_title(f"{label}: light return vs tilt", fontsize=8)
            save_figure(f2, looks_dir / f"{key}_lp_map.png", dpi=80)
            plt.close(f2)
            print(
                f"{label}: ASET leak {zones['leak']:.3f} (centre {zones['leak_centre']:.3f}, crown "
                f"{zones['leak_crown']:.3f}; leak-dominated area {zones['area_leak']:.3f}, centre "
                f"{zones['area_leak_centre']:.3f}, crown {zones['area_leak_crown']:.3f}), red "
                f"{zones['red']:.3f}; Ideal Scope leak {ifr['leak']:.3f}; arrows "
                f"{n_arrows or arrows_verdict}, hearts {n_hearts or hearts_verdict}; bright "
                f"{b_fr['bright']:.3f} dark {b_fr['dark']:.3f}; light return over the map {lr_mean:.3f}; "
                f"{renders} renders, {seconds:.0f} s",
                flush=True,
            )
    fig.tight_layout()
    save_figure(fig, out / "grading_looks.png", dpi=90)
    plt.close(fig)
    fig, axs = plt.subplots(len(strips), 1, figsize=(9, 3.0 * len(strips)), squeeze=False)
    for ax, (label, strip) in zip(axs[:, 0], strips, strict=True):
        ax.imshow(strip, interpolation="nearest")
        ax.set_axis_off()
        ax.set_title(f"{label}: tilt 0-{strip_tilts[-1]:g}° (ISO + head above, spots below)", fontsize=8)
    fig.tight_layout()
    save_figure(fig, out / "grading_tilt_strips.png", dpi=90)
    plt.close(fig)
    write_text_atomic(out / "grading_gallery.json", json.dumps(readout, indent=1) + "\n")
    print(f"wrote {out / 'grading_looks.png'}, {out / 'grading_tilt_strips.png'}, {looks_dir}/, and .json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
