"""`warpoptics chart`: the polarizing microscope's charts and figures, from the coherent plate.

    warpoptics chart michel-levy -o chart.png [--max-retardation 2000] [--max-thickness 50]
    warpoptics chart conoscope -o figure.png --material calcite --thickness 0.25 [--axis 0 0 1]
                               [--na 0.5] [--wavelength 589.3 | --white] [--size 201]
    warpoptics chart colour --material quartz --thickness 0.03 [--axis 1 1 0]
    (conoscope, colour: [--accessory-nm 550 --accessory-deg 45] adds a first-order red plate)

``michel-levy``: interference colour against retardation (x) with thickness (y) and lines of
constant birefringence (Delta = d * birefringence); the colours are those of a plate between
crossed polarizers in its 45-degree position (``pipelines/microscope.py``).  ``conoscope``: the
interference figure of a plate in convergent light (Bertrand lens), monochromatic or white.
``colour``: the interference colour and retardation of one plate (orthoscopic).  Optical
activity (quartz along its axis) is not modelled.
"""

from __future__ import annotations

import argparse

import numpy as np

from .. import validate as val
from ..errors import InputError
from ..pipelines.microscope import MAX_CHART_RETARDATION_NM
from ..spectra import LAMBDA_MAX, LAMBDA_MIN

__all__ = ["draw_michel_levy", "draw_conoscope", "register", "run"]

# birefringence lines drawn on the chart and the minerals named beside them
_LINES = (0.001, 0.002, 0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.15, 0.2)
_MINERALS = ("quartz", "sapphire", "tourmaline", "peridot", "calcite")


def _mineral_birefringence() -> list[tuple[str, float]]:
    from .. import materials

    out = []
    for name in _MINERALS:
        try:
            mat = materials.get(name)
        except (KeyError, InputError):  # pragma: no cover - the library names are fixed
            continue
        n = np.asarray(mat.n(589.3), dtype=np.float64).ravel()  # type: ignore[attr-defined]
        out.append((name, float(abs(n[-1] - n[0]))))
    return out


def draw_michel_levy(chart, path, *, max_thickness_um: float = 50.0):
    """The chart as a figure: colours against retardation, thickness on y, birefringence lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..film.image import save_figure

    ret = chart.retardation_nm
    rmax = float(ret[-1])
    fig, ax = plt.subplots(figsize=(11, 5.2))
    img = np.asarray(chart.srgb)[None, :, :].repeat(4, axis=0)
    ax.imshow(img, extent=(0.0, rmax, 0.0, max_thickness_um), aspect="auto", interpolation="bilinear")
    for dn in _LINES:
        t_end = min(max_thickness_um, rmax / (1000.0 * dn))
        r_end = t_end * 1000.0 * dn
        ax.plot([0.0, r_end], [0.0, t_end], color="k", lw=0.5, alpha=0.7)
        if t_end >= max_thickness_um - 1e-9:
            ax.text(r_end, max_thickness_um * 1.01, f"{dn:g}", fontsize=7, ha="center", va="bottom")
        else:
            ax.text(rmax * 1.005, t_end, f"{dn:g}", fontsize=7, ha="left", va="center")
    for j, (name, dn) in enumerate(sorted(_mineral_birefringence(), key=lambda m: m[1])):
        f = 0.93 if j % 2 == 0 else 0.85  # neighbouring lines: labels at two heights
        t = min(max_thickness_um * f, rmax / (1000.0 * dn) * f)
        t_top = min(max_thickness_um, rmax / (1000.0 * dn))
        ax.plot([0.0, t_top * 1000.0 * dn], [0.0, t_top], color="k", lw=0.5, ls=":", alpha=0.8)
        ax.text(t * 1000.0 * dn, t, name, fontsize=6, rotation=0, ha="left", va="bottom", alpha=0.8)
    ax.axhline(30.0, color="w", lw=0.6, ls="--")
    ax.text(4.0, 30.5, "30 µm thin section", fontsize=7, color="w", va="bottom")
    orders = int(rmax // 550.0)
    every = max(1, -(-orders // 40))  # at most 40 order lines (a 1e5 nm chart has 181 orders)
    for m in range(every, orders + 1, every):
        ax.axvline(550.0 * m, color="w", lw=0.4, alpha=0.6)
        ax.text(550.0 * (m - 0.5), 1.0, f"order {m}", fontsize=7, ha="center", color="w")
    ax.set_xlim(0.0, rmax)
    ax.set_ylim(0.0, max_thickness_um)
    ax.set_xlabel("retardation Δ = d·|n_slow − n_fast| (nm)")
    ax.set_ylabel("thickness d (µm)")
    ax.set_title(
        "Michel-Lévy chart: plate between crossed polarizers at 45°, o and e waves added coherently "
        f"(warpoptics; {chart.illuminant}, lines: birefringence)",
        fontsize=8,
        pad=14,
    )
    fig.tight_layout()
    out = save_figure(fig, path, dpi=120)
    plt.close(fig)
    return out


def draw_conoscope(figure, path, *, title: str = ""):
    """The conoscopic figure as an image with its aperture circle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..film.image import save_figure

    fig, ax = plt.subplots(figsize=(4.4, 4.6))
    na = figure.numerical_aperture
    ax.imshow(figure.srgb, extent=(-na, na, -na, na), interpolation="bilinear")
    ax.add_patch(plt.Circle((0, 0), na, fill=False, color="0.5", lw=0.6))
    ax.set_xlabel("n sin θ cos ψ (polarizer →)", fontsize=7)
    ax.set_ylabel("n sin θ sin ψ (analyzer ↑)", fontsize=7)
    ax.tick_params(labelsize=6)
    ax.set_title(title, fontsize=7)
    fig.tight_layout()
    out = save_figure(fig, path, dpi=120)
    plt.close(fig)
    return out


def _material(name: str):
    from .. import materials

    try:
        return materials.get(name)
    except (KeyError, InputError) as exc:
        why = exc.message if isinstance(exc, InputError) else "unknown material"
        allowed = exc.allowed if isinstance(exc, InputError) else None
        raise InputError(why, field="--material", value=name, allowed=allowed) from None


def run(args) -> int:
    from ..atomic import check_writable
    from ..pipelines import microscope
    from ..spectra import ILLUMINANTS

    if args.illuminant not in ILLUMINANTS:
        raise InputError(
            "unknown illuminant", field="--illuminant", value=args.illuminant, allowed=", ".join(ILLUMINANTS)
        )
    if args.output is not None and args.chart != "colour":
        check_writable(args.output)  # before the work

    if args.chart == "michel-levy":
        if args.output is None:
            raise InputError("an output file is required", field="-o")
        chart = microscope.michel_levy_chart(
            max_retardation_nm=args.max_retardation, illuminant=args.illuminant, device=args.device
        )
        path = draw_michel_levy(chart, args.output, max_thickness_um=args.max_thickness)
        print(f"wrote {path}")
        return 0
    mat = _material(args.material)
    axis = tuple(args.axis) if args.axis else None
    if args.thickness is None:
        raise InputError("the plate thickness (mm) is required", field="--thickness")
    if args.chart == "colour":
        ic = microscope.interference_colour(
            mat,
            args.thickness,
            optic_axis=axis,
            illuminant=args.illuminant,
            accessory_nm=args.accessory_nm,
            accessory_deg=args.accessory_deg,
            device=args.device,
        )
        s = np.round(np.asarray(ic.srgb) * 255).astype(int)
        print(f"material       {mat.name}")
        print(f"thickness      {args.thickness * 1000:g} µm")
        print(f"retardation    {ic.retardation_nm:.1f} nm (at {ic.reference_nm:g} nm)")
        print(f"sRGB           #{s[0]:02x}{s[1]:02x}{s[2]:02x}")
        print(f"CIELAB         L={ic.lab[0]:.1f} a={ic.lab[1]:.1f} b={ic.lab[2]:.1f}")
        print("optical activity: not modelled")
        return 0
    if args.output is None:
        raise InputError("an output file is required", field="-o")
    wl = None if args.white else args.wavelength
    optic_axis = axis if axis else (0.0, 0.0, 1.0)
    fig = microscope.conoscopic_figure(
        mat,
        args.thickness,
        size=args.size,
        numerical_aperture=args.na,
        wavelength_nm=wl,
        illuminant=args.illuminant,
        optic_axis=optic_axis,
        accessory_nm=args.accessory_nm,
        accessory_deg=args.accessory_deg,
        device=args.device,
    )
    light = "white light" if wl is None else f"{wl:g} nm"
    title = (
        f"{mat.name}, {args.thickness:g} mm, axis {optic_axis}, NA {args.na:g}, {light}, crossed polarizers"
    )
    path = draw_conoscope(fig, args.output, title=title)
    print(f"wrote {path}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "chart",
        help="polarizing microscope: Michel-Lévy chart, conoscopic figure, interference colour of a plate",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("chart", choices=["michel-levy", "conoscope", "colour"])
    p.add_argument("-o", "--output", default=None, help="output figure (.png, .pdf, .svg)")
    p.add_argument(
        "--max-retardation",
        # at least 1 nm: a narrower axis is black throughout, and at 1e-9 nm matplotlib's tick
        # labels overflowed its glyph rasterizer (a traceback)
        type=val.flag(float, lo=1.0, hi=MAX_CHART_RETARDATION_NM, unit="nm"),
        default=2000.0,
        help=f"michel-levy: largest retardation (nm; default 2000, 1 to {MAX_CHART_RETARDATION_NM:g})",
    )
    p.add_argument(
        "--max-thickness",
        type=val.flag(float, lo=0.0, lo_open=True, hi=1.0e5, unit="µm"),
        default=50.0,
        help="michel-levy: largest thickness (µm; default 50)",
    )
    p.add_argument("--illuminant", default="D65", help="CIE illuminant (default D65)")
    p.add_argument("--material", default="calcite", help="conoscope/colour: a library material")
    p.add_argument(
        "--thickness",
        type=val.flag(float, lo=0.0, hi=1.0e9, unit="mm"),
        default=None,
        help="conoscope/colour: plate thickness (mm)",
    )
    p.add_argument(
        "--axis",
        type=val.flag(float),
        nargs=3,
        default=None,
        help="optic axis (world; z = microscope axis)",
    )
    p.add_argument(
        "--na",
        type=val.flag(float, lo=0.0, lo_open=True, hi=1.0, hi_open=True),
        default=0.5,
        help="conoscope: numerical aperture (default 0.5; in air < 1)",
    )
    p.add_argument(
        "--wavelength",
        type=val.flag(float, lo=LAMBDA_MIN, hi=LAMBDA_MAX, unit="nm"),
        default=589.3,
        help=f"conoscope: wavelength (nm, {LAMBDA_MIN:g} to {LAMBDA_MAX:g})",
    )
    p.add_argument("--white", action="store_true", help="conoscope: white light instead of --wavelength")
    p.add_argument(
        "--size",
        type=val.flag(int, lo=8, hi=4096, unit="pixels"),
        default=201,
        help="conoscope: image size (pixels, 8 to 4096)",
    )
    p.add_argument(
        "--accessory-nm",
        type=val.flag(float, lo=0.0, hi=1.0e5, unit="nm"),
        default=0.0,
        help="accessory plate before the analyzer: retardation in nm (550 first-order red, 147 quarter-wave)",
    )
    p.add_argument(
        "--accessory-deg",
        type=val.flag(float, lo=-360.0, hi=360.0, unit="degrees"),
        default=45.0,
        help="its slow direction (default 45: NE-SW)",
    )
    p.set_defaults(func=run)
