"""`warpoptics spectrum -o FILE`: the visible spectrum, naively clipped and Smits–Meyer clipped.

Reproduces the idea of Smits & Meyer 1990, fig. 4: monochromatic colours lie outside every
display gamut; per-channel clipping changes their lightness, the Smits–Meyer clip holds Y and
moves toward the neutral axis.  Prints the hue and luminance changes of both.
"""

from __future__ import annotations

import numpy as np


def spectral_locus(wavelength_nm, luminance_scale: float = 0.6) -> np.ndarray:
    """XYZ of equal-power monochromatic lights, scaled so that Y(555 nm) ~= ``luminance_scale``."""
    from ..spectra import cmf

    return cmf(wavelength_nm) * luminance_scale


def clip_comparison(wavelength_nm, luminance_scale: float = 0.6, *, device=None) -> dict:
    """Clip the spectral locus both ways; return linear RGB and the CIELAB hue/Y changes."""
    from ..color import clip_naive, gamut_clip, srgb_linear_to_xyz, xyz_to_lab

    xyz = spectral_locus(wavelength_nm, luminance_scale)
    rgb_sm = gamut_clip(xyz, 1.0, device=device)
    rgb_naive = clip_naive(xyz)
    out = {"xyz": xyz, "rgb_smits_meyer": rgb_sm, "rgb_naive": rgb_naive}
    lab = xyz_to_lab(xyz)
    for key, rgb in (("smits_meyer", rgb_sm), ("naive", rgb_naive)):
        lab_c = xyz_to_lab(srgb_linear_to_xyz(rgb))
        dh = np.degrees(np.arctan2(lab_c[..., 2], lab_c[..., 1]) - np.arctan2(lab[..., 2], lab[..., 1]))
        out[f"hue_shift_{key}"] = np.abs((dh + 180.0) % 360.0 - 180.0)
        out[f"dY_{key}"] = srgb_linear_to_xyz(rgb)[..., 1] - xyz[..., 1]
    return out


def draw(path, *, start: float = 380.0, stop: float = 780.0, device=None) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..color import encode_srgb
    from ..film.image import save_figure

    wl = np.linspace(start, stop, 801)
    res = clip_comparison(wl, device=device)
    fig, axes = plt.subplots(3, 1, figsize=(8, 4.6), sharex=True, gridspec_kw={"height_ratios": [1, 1, 1.4]})
    for ax, key, title in (
        (axes[0], "rgb_naive", "per-channel clip (lightness and hue change)"),
        (axes[1], "rgb_smits_meyer", "Smits–Meyer clip (constant Y, toward the neutral axis)"),
    ):
        strip = encode_srgb(res[key])[None, :, :].repeat(40, axis=0)
        ax.imshow(strip, extent=(start, stop, 0, 1), aspect="auto")
        ax.set_yticks([])
        ax.set_title(title, fontsize=9)
    ax = axes[2]
    ax.plot(wl, res["hue_shift_naive"], label="per-channel: |Δh| (deg)")
    ax.plot(wl, res["hue_shift_smits_meyer"], label="Smits–Meyer: |Δh| (deg)")
    ax.set_ylabel("CIELAB hue change (deg)", fontsize=8)
    ax2 = ax.twinx()
    ax2.plot(wl, res["dY_naive"], "k:", lw=1, label="per-channel: ΔY")
    ax2.plot(wl, res["dY_smits_meyer"], "k--", lw=1, label="Smits–Meyer: ΔY")
    ax2.set_ylabel("ΔY", fontsize=8)
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=7, loc="upper center", ncol=2)
    ax.set_xlabel("wavelength (nm)")
    fig.suptitle("The visible spectrum on an sRGB display", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)
    return res


def run(args) -> int:
    res = draw(args.output, device=args.device)
    inside = np.asarray(res["xyz"])[:, 1] > 0.01
    for key, name in (("naive", "per-channel clip"), ("smits_meyer", "Smits–Meyer clip")):
        dh = res[f"hue_shift_{key}"][inside]
        dy = np.abs(res[f"dY_{key}"][inside])
        print(
            f"{name:18s} hue change mean {dh.mean():5.1f} deg, max {dh.max():5.1f} deg; "
            f"|dY| max {dy.max():.4f}"
        )
    print(f"wrote {args.output}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("spectrum", help="draw the visible spectrum, naively and Smits–Meyer clipped")
    p.add_argument("-o", "--output", required=True, help="output image (PNG, PDF, SVG)")
    p.set_defaults(func=run)
