"""`warpoptics thinfilm table`: Newton's colour sequence as a labelled strip (Smits & Meyer 1990).

    warpoptics thinfilm table [--phase-change] [--model exact|smits-meyer] [--multilayer] -o FILE

Draws the colour table of a single film against its optical thickness t' = t n cos(theta) in nm
(eq. 11; a second axis gives the film thickness for ``--n-film``), or with ``--multilayer`` the
Morpho table against the angle of incidence.  The top strip is the Smits–Meyer clipped colour
(constant luminance, toward the neutral axis), the middle one the per-channel clip, the bottom
panel the luminance Y.  ``-o`` ending in ``.csv`` writes the table values instead of a figure.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["build_table", "draw_table", "write_csv", "register", "run"]


def build_table(args):
    from ..optics import thinfilm as tf

    if args.multilayer:
        return tf.multilayer_color_table(
            model=args.model,
            d1_nm=args.d1,
            d2_nm=args.d2,
            n=args.n_layer,
            layers=args.layers,
            count=args.count,
            illuminant=args.illuminant,
            device=args.device,
        )
    return tf.film_color_table(
        phase_change=args.phase_change,
        model=args.model,
        max_optical_thickness_nm=args.max_thickness,
        count=args.count,
        n_film=args.n_film,
        n_substrate=args.n_substrate,
        illuminant=args.illuminant,
        device=args.device,
    )


def write_csv(table, path) -> Path:
    from ..atomic import atomic_path

    header = f"{table.quantity},X,Y,Z,R_linear,G_linear,B_linear"
    data = np.column_stack([table.axis, table.xyz, table.rgb])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=header, comments="", fmt="%.6g")
    return Path(path)


def draw_table(table, path, *, n_film: float | None = None) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..atomic import atomic_path
    from ..color import clip_naive, encode_srgb

    x = table.axis
    lo, hi = float(x[0]), float(x[-1])
    fig, axes = plt.subplots(
        3, 1, figsize=(9, 4.4), sharex=True, gridspec_kw={"height_ratios": [1.2, 0.6, 1.0]}
    )
    strips = (
        (axes[0], table.rgb, "Smits–Meyer clip (constant Y)"),
        (axes[1], clip_naive(table.xyz * table.exposure), "per-channel clip"),
    )
    for ax, rgb, label in strips:
        img = encode_srgb(np.asarray(rgb))[None, :, :].repeat(8, axis=0)
        ax.imshow(img, extent=(lo, hi, 0, 1), aspect="auto", interpolation="bilinear")
        ax.set_yticks([])
        ax.set_ylabel(label, fontsize=7, rotation=0, ha="right", va="center")
    if table.quantity == "optical_thickness_nm":
        # Newton's orders: with the phase change the m-th order spans t' = (m-1..m) * 275 nm
        # (half of 550 nm), the dark bands of eq. 7/8 at multiples of lambda/2 (or lambda/4 shifted)
        for m in range(1, int(hi // 275.0) + 1):
            axes[0].axvline(m * 275.0, color="k", lw=0.5, alpha=0.5)
            axes[0].text(
                (m - 0.5) * 275.0,
                1.04,
                f"order {m}",
                ha="center",
                va="bottom",
                fontsize=7,
                transform=axes[0].transData,
            )
        axes[2].set_xlabel("optical thickness t' = t n cos θ (nm)")
        if n_film:
            sec = axes[0].secondary_xaxis("top", functions=(lambda t: t / n_film, lambda t: t * n_film))
            sec.set_xlabel(f"film thickness at normal incidence, n = {n_film:g} (nm)", fontsize=8)
            sec.tick_params(labelsize=7)
    else:
        axes[2].set_xlabel("angle of incidence (degrees)")
    ax = axes[2]
    ax.plot(x, table.xyz[:, 1], color="k", lw=1)
    ax.set_ylabel("Y (reflected)", fontsize=8)
    ax.set_xlim(lo, hi)
    ax.grid(alpha=0.3)
    phase = "with phase change" if table.phase_change else "without phase change"
    kind = "multilayer" if table.quantity == "angle_deg" else f"single film, {phase}"
    fig.suptitle(
        f"Newton's colours — {kind}; model: {table.model} ({table.description}); {table.illuminant}",
        fontsize=8,
        y=0.995,
    )
    fig.tight_layout()
    suffix = Path(path).suffix.lower().lstrip(".") or "png"
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format=suffix)
    plt.close(fig)
    return Path(path)


def _check_args(args) -> None:
    """Numbers a film can have: finite, indices >= 1 (the CLI takes real, lossless indices),
    thicknesses >= 0, at least one layer."""
    import math

    checks = [
        ("--max-thickness", args.max_thickness, 0.0, 1.0e6, True),
        ("--n-film", args.n_film, 1.0, 20.0, False),
        ("--n-substrate", args.n_substrate, 1.0, 20.0, False),
        ("--d1", args.d1, 0.0, 1.0e6, False),
        ("--d2", args.d2, 0.0, 1.0e6, False),
        ("--n-layer", args.n_layer, 1.0, 20.0, False),
        ("--layers", args.layers, 1, 1000, False),
    ]
    for name, v, lo, hi, lo_open in checks:
        if v is None:
            continue
        if not math.isfinite(v) or v < lo or v > hi or (lo_open and v == lo):
            rng = f"{'>' if lo_open else '>='} {lo:g} and <= {hi:g}"
            raise InputError("out of range", field=name, value=v, allowed=rng)


def run(args) -> int:
    if args.action != "table":  # pragma: no cover - argparse restricts the choices
        raise InputError("unknown thinfilm action", field="action", value=args.action, allowed="table")
    if not 2 <= args.count <= 100_000:
        raise InputError("--count out of range", field="--count", value=args.count, allowed="2 to 100000")
    _check_args(args)
    out = Path(args.output)
    if out.suffix.lower() not in (".png", ".pdf", ".svg", ".csv"):
        raise InputError(
            "unsupported output type", file=str(out), field="-o", allowed=".png, .pdf, .svg, .csv"
        )
    table = build_table(args)
    if out.suffix.lower() == ".csv":
        write_csv(table, out)
    else:
        draw_table(table, out, n_film=None if args.multilayer else args.n_film)
    i = int(np.argmax(table.xyz[:, 1]))
    unit = "nm" if table.quantity == "optical_thickness_nm" else "deg"
    print(
        f"{table.model} table, {table.axis.size} entries, {table.axis[0]:g}-{table.axis[-1]:g} {unit}; "
        f"brightest Y={table.xyz[i, 1]:.4f} at {table.axis[i]:g} {unit}; "
        f"exposure {table.exposure:.4g}; wrote {out}"
    )
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "thinfilm", help="thin-film interference colours (Newton's colours, Smits & Meyer 1990)"
    )
    p.add_argument("action", choices=["table"], help="table: draw the colour table as a labelled strip")
    p.add_argument(
        "-o", "--output", required=True, help="output figure (.png, .pdf, .svg) or .csv of the table"
    )
    p.add_argument(
        "--phase-change", action="store_true", help="film between lower-index media (eq. 7; black film)"
    )
    p.add_argument(
        "--model", choices=["exact", "smits-meyer"], default="smits-meyer", help="default: smits-meyer"
    )
    p.add_argument(
        "--multilayer", action="store_true", help="Morpho multilayer table against angle (eq. 9, 14)"
    )
    p.add_argument("--max-thickness", type=float, default=1500.0, help="largest optical thickness t' (nm)")
    p.add_argument("--count", type=int, default=None, help="table entries (default 751 film, 90 multilayer)")
    p.add_argument("--n-film", type=float, default=1.33, help="film index for the exact model (default 1.33)")
    p.add_argument(
        "--n-substrate",
        type=float,
        default=None,
        help="substrate index, exact model (default 1.0 / 1.77 without)",
    )
    p.add_argument("--d1", type=float, default=150.0, help="multilayer air spacing d1 (nm)")
    p.add_argument("--d2", type=float, default=50.0, help="multilayer layer thickness d2 (nm)")
    p.add_argument("--n-layer", type=float, default=1.53, help="multilayer layer index (default 1.53)")
    p.add_argument("--layers", type=int, default=12, help="number of layers (default 12)")
    p.add_argument("--illuminant", default="D65", help="E, D65 or A")
    p.set_defaults(func=_run_with_defaults)


def _run_with_defaults(args) -> int:
    if args.count is None:
        args.count = 90 if args.multilayer else 751
    return run(args)
