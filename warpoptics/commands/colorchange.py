"""`warpoptics colorchange MATERIAL|SPECTRUM`: colour change of a plate or a spectrum between two lights.

``MATERIAL`` is a library name (``colour_change_garnet``, ``ruby``, ...): the spectrum is the
transmittance of a polished plate ``--thickness`` mm thick (``metrics.plate_transmittance``).
``SPECTRUM`` is a CSV file of wavelength (nm), transmittance or reflectance (0..1).  Prints
CIELAB under each illuminant, the hue-angle change and ΔE00 (``metrics.colour_change``);
``--plot FILE`` draws the spectrum with the two colours.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError


def _spectrum(source: str, thickness: float) -> tuple[np.ndarray, np.ndarray, str]:
    from ..metrics import plate_transmittance
    from ..spectra import grid

    if Path(source).suffix.lower() == ".csv":
        p = Path(source)
        if not p.is_file():
            raise InputError("spectrum file not found", file=source, field="SPECTRUM")
        wl, values = _read_spectrum_csv(p)
        return wl, values, f"{p.name}"
    g = grid()
    return g, plate_transmittance(source, thickness, g), f"{source}, {thickness:g} mm plate"


def _read_spectrum_csv(p: Path) -> tuple[np.ndarray, np.ndarray]:
    """Wavelengths (nm) and values of a two-column CSV, every error naming the file, the column
    and the row: at least two rows, wavelengths finite and increasing inside 200-2000 nm, values
    finite and >= 0."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numpy's "empty input file": said below
            data = np.loadtxt(p, delimiter=",", comments="#", ndmin=2)
    except (ValueError, UnicodeDecodeError) as exc:
        why = " ".join(str(exc).split())[:120]
        raise InputError(f"not a CSV of numbers ({why})", file=str(p)) from None
    if data.ndim != 2 or data.shape[0] == 0:
        raise InputError("holds no rows: expected wavelength (nm), value per line", file=str(p))
    if data.shape[1] < 2:
        raise InputError(
            "needs two columns: wavelength (nm), value",
            file=str(p),
            field="columns",
            value=int(data.shape[1]),
        )
    if data.shape[0] < 2:
        raise InputError(
            "needs at least two rows (wavelengths)", file=str(p), field="rows", value=int(data.shape[0])
        )
    wl, v = data[:, 0], data[:, 1]
    for name, col, ok, allowed in (
        ("wavelength (column 1)", wl, np.isfinite(wl) & (wl >= 200.0) & (wl <= 2000.0), "200 to 2000 nm"),
        ("value (column 2)", v, np.isfinite(v) & (v >= 0.0), "finite numbers >= 0"),
    ):
        if not np.all(ok):
            row = int(np.argmin(ok))
            raise InputError(
                f"row {row + 1}: out of range",
                file=str(p),
                field=name,
                value=float(col[row]),
                allowed=allowed,
            )
    steps = np.diff(wl)
    if np.any(steps <= 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise InputError(
            f"row {row + 1}: wavelengths must increase (row {row} has {wl[row - 1]:g})",
            file=str(p),
            field="wavelength (column 1)",
            value=float(wl[row]),
        )
    return wl, v


def _plot(path, wl, values, result, title) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import colour
    import matplotlib.pyplot as plt

    from ..film.image import save_figure

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(8, 3), gridspec_kw={"width_ratios": [3, 1]})
    ax.plot(wl, values, "k")
    ax.set_xlim(360, 830)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("transmittance / reflectance")
    ax.set_title(title, fontsize=9)
    for i, (name, lab) in enumerate(zip(result["illuminants"], result["lab"], strict=True)):
        xyz = colour.Lab_to_XYZ(lab)
        rgb = np.clip(colour.XYZ_to_sRGB(xyz), 0.0, 1.0)
        ax2.add_patch(plt.Rectangle((i, 0), 1, 1, color=rgb))
        ax2.text(i + 0.5, -0.12, name, ha="center", fontsize=8)
    ax2.set_xlim(0, 2)
    ax2.set_ylim(-0.2, 1)
    ax2.axis("off")
    ax2.set_title(f"Δh {result['delta_hue']:.1f}°, ΔE00 {result['delta_e00']:.2f}", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)


def run(args) -> int:
    from .. import validate as val
    from ..metrics import colour_change
    from ..spectra import light_spectrum_row

    names = [s.strip() for s in args.illuminants.split(",") if s.strip()]
    if len(names) != 2:
        raise InputError("give two illuminants, e.g. D65,A", field="--illuminants", value=args.illuminants)
    for n in names:
        light_spectrum_row(n, field="--illuminants")
    val.number(args.thickness, field="--thickness", lo=0.0, hi=1.0e4)
    wl, values, title = _spectrum(args.source, args.thickness)
    r = colour_change(wl, values, illuminants=names)
    print(f"colour change of {title}")
    for name, lab, c, h in zip(r["illuminants"], r["lab"], r["chroma"], r["hue"], strict=True):
        print(
            f"  {name:8s} L* {lab[0]:6.2f}  a* {lab[1]:7.2f}  b* {lab[2]:7.2f}"
            f"  C*ab {c:6.2f}  h_ab {h:6.1f} deg"
        )
    print(f"  hue-angle change {r['delta_hue']:.1f} deg, CIEDE2000 {r['delta_e00']:.2f}")
    if args.plot:
        _plot(args.plot, wl, values, r, title)
        print(f"wrote {args.plot}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "colorchange", help="CIELAB hue change and ΔE00 of a plate or spectrum between two lights"
    )
    p.add_argument("source", metavar="MATERIAL|SPECTRUM", help="a library material or a CSV (nm, value)")
    p.add_argument(
        "--thickness", type=float, default=4.0, help="plate thickness in mm (materials; default 4)"
    )
    p.add_argument("--illuminants", default="D65,A", help="two light spectra (default D65,A)")
    p.add_argument("--plot", default=None, help="also draw the spectrum and both colours (PNG, PDF, SVG)")
    p.set_defaults(func=run)
