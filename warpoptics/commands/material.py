"""`warpoptics material NAME [--plot FILE]`: a library material's optical constants.

`warpoptics material fit HOST --spectrum FILE.csv ... | --lab L,a,b --thickness MM ...`: the
chromophore concentrations of a host crystal that reproduce a measured absorption spectrum or a
target colour (:func:`warpoptics.materials.fit.fit_chromophores`), with the fit's residual.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

#: wavelengths (nm) at which the summary reports 2V of a biaxial stone (dispersion of the optic axes)
TWO_V_NM = (450.0, 550.0, 589.3, 650.0)


def _biaxial_summary(mat) -> list[str]:
    from ..materials import abbe_number, dispersion_bg, rgb3_alpha_of

    n = mat.n(589.3)
    two_v = mat.two_v(np.array(TWO_V_NM))
    ch = ("alpha", "beta", "gamma")
    lines = [
        f"nD (589.3 nm)  alpha {n[0]:.4f}  beta {n[1]:.4f}  gamma {n[2]:.4f}",
        f"birefringence  {n[2] - n[0]:.4f} (n_gamma - n_alpha at 589.3 nm)",
        f"2V             {float(mat.two_v(589.3)):.2f} deg, optic sign {mat.optic_sign} "
        f"({'Z' if mat.optic_sign == '+' else 'X'} is the acute bisectrix)",
        "2V(lambda)     " + "  ".join(f"{lam:g} nm {v:.2f}" for lam, v in zip(TWO_V_NM, two_v, strict=True)),
        "B-G dispersion " + "  ".join(f"{c} {dispersion_bg(mat, channel=c):.4f}" for c in ch),
        "Abbe V_d       " + "  ".join(f"{c} {abbe_number(mat, channel=c):.1f}" for c in ch),
    ]
    for name, row in zip("XYZ", mat.crystal_axes, strict=True):
        lines.append(f"axis {name}         ({row[0]:.3f}, {row[1]:.3f}, {row[2]:.3f})")
    rgb = mat.rgb3_alpha if mat.rgb3_alpha is not None else rgb3_alpha_of(mat)
    if max(max(t) for t in rgb) > 0:
        lines.append(
            "rgb3 alpha     "
            + " ".join(f"{a} ({', '.join(f'{v:.4g}' for v in t)})" for a, t in zip("XYZ", rgb, strict=True))
            + " 1/mm"
        )
    return lines


def _summary(mat) -> list[str]:
    from ..materials import Biaxial, Uniaxial, abbe_number, dispersion_bg, rgb3_alpha_of

    lo, hi = mat.wavelength_range_nm
    lines = [f"material       {mat.name}"]
    kind = "biaxial" if isinstance(mat, Biaxial) else "uniaxial" if isinstance(mat, Uniaxial) else "isotropic"
    lines.append(f"type           {kind}")
    lines.append(f"range          {lo:g}-{hi:g} nm")
    if isinstance(mat, Biaxial):
        return [*lines, *_biaxial_summary(mat), f"source         {mat.source}"]
    if isinstance(mat, Uniaxial):
        n = mat.n(589.3)
        lines.append(f"nD (589.3 nm)  o {n[0]:.4f}  e {n[1]:.4f}")
        lines.append(f"birefringence  {n[1] - n[0]:+.4f} (n_e - n_o at 589.3 nm)")
        lines.append(
            f"B-G dispersion o {dispersion_bg(mat, channel='o'):.4f}  e {dispersion_bg(mat, channel='e'):.4f}"
        )
        lines.append(
            f"Abbe V_d       o {abbe_number(mat, channel='o'):.1f}  e {abbe_number(mat, channel='e'):.1f}"
        )
        ax = mat.optic_axis
        lines.append(f"optic axis     ({ax[0]:.3f}, {ax[1]:.3f}, {ax[2]:.3f})")
    else:
        lines.append(f"nD (589.3 nm)  {float(mat.n(589.3)):.4f}")
        lines.append("birefringence  0 (isotropic)")
        lines.append(f"B-G dispersion {dispersion_bg(mat):.4f}")
        lines.append(f"Abbe V_d       {abbe_number(mat):.1f}")
    o, e = mat.rgb3_alpha if mat.rgb3_alpha is not None else rgb3_alpha_of(mat)
    if max(max(o), max(e)) > 0:
        fo = ", ".join(f"{v:.4g}" for v in o)
        fe = ", ".join(f"{v:.4g}" for v in e)
        lines.append(f"rgb3 alpha     o ({fo}) e ({fe}) 1/mm")
    lines.append(f"source         {mat.source}")
    return lines


def _figure(mat):
    """The --plot figure: n(λ) and alpha(λ); a biaxial stone adds 2V(λ) between them (three
    panels: n_alpha/beta/gamma, 2V, alpha_X/Y/Z)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..materials import Biaxial, Uniaxial

    lo, hi = mat.wavelength_range_nm
    lam = np.linspace(max(lo, 360.0), min(hi, 830.0), 471)
    if isinstance(mat, Biaxial):
        fig, (a1, av, a2) = plt.subplots(1, 3, figsize=(14, 4))
        n, alpha = mat.n(lam), mat.alpha(lam)
        for j, (c, d) in enumerate(zip(("alpha", "beta", "gamma"), "XYZ", strict=True)):
            a1.plot(lam, n[:, j], label=f"n_{c} (D along {d})")
            a2.plot(lam, alpha[:, j], label=f"alpha_{d}")
        two_v = mat.two_v(lam)
        av.plot(lam, two_v, label=f"2V ({mat.optic_sign})")
        # at least a 2-degree span: n is float32, so a stone whose three indices share one
        # dispersion shows 1e-3-degree rounding steps that autoscaling would blow up
        mid, half = 0.5 * (two_v.max() + two_v.min()), max(1.0, 0.55 * (two_v.max() - two_v.min()))
        av.set_ylim(mid - half, mid + half)
        av.set_xlabel("wavelength (nm)")
        av.set_ylabel("optic-axial angle 2V (degrees)")
        av.legend()
        av.grid(alpha=0.3)
    elif isinstance(mat, Uniaxial):
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        n, alpha = mat.n(lam), mat.alpha(lam)
        a1.plot(lam, n[:, 0], label="n_o")
        a1.plot(lam, n[:, 1], label="n_e")
        a2.plot(lam, alpha[:, 0], label="alpha_o")
        a2.plot(lam, alpha[:, 1], label="alpha_e")
    else:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        a1.plot(lam, mat.n(lam), label="n")
        a2.plot(lam, mat.alpha(lam), label="alpha")
    a1.set_xlabel("wavelength (nm)")
    a1.set_ylabel("refractive index")
    a2.set_xlabel("wavelength (nm)")
    a2.set_ylabel("absorption coefficient (1/mm, base e)")
    for a in (a1, a2):
        a.legend()
        a.grid(alpha=0.3)
    fig.suptitle(mat.name)
    fig.tight_layout()
    return fig


def _plot(mat, path: str) -> None:
    import matplotlib.pyplot as plt

    from ..film.image import save_figure

    fig = _figure(mat)
    save_figure(fig, path, field="--plot", dpi=100)
    plt.close(fig)


#: the options that belong to `material fit` (argparse dest names)
_FIT_OPTIONS = ("spectrum", "lab", "thickness", "path_mm", "chromophores", "polarization", "baseline")


def _numbers(text: str, count: int, option: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != count:
        raise InputError(f"needs {count} comma-separated numbers", field=option, value=text)
    return values


def _fit(args) -> int:
    from ..materials.fit import fit_chromophores

    if not args.host:
        raise InputError("name the host crystal: warpoptics material fit HOST ...", field="HOST")
    if (args.spectrum is None) == (args.lab is None):
        raise InputError("give --spectrum FILE.csv or --lab L,a,b (one of them)", field="--spectrum/--lab")
    common = dict(chromophores=args.chromophores)
    if args.spectrum is not None:
        result = fit_chromophores(
            args.host,
            spectrum=args.spectrum,
            quantity=args.quantity,
            path_mm=args.path_mm,
            polarization=args.polarization,
            baseline=args.baseline,
            wavelength_range_nm=_numbers(args.range, 2, "--range"),  # type: ignore[arg-type]
            **common,
        )
    else:
        target = _numbers(args.lab, 3, "--lab")
        if args.thickness is None:
            raise InputError(
                "a colour fit needs --thickness MM (the stone's path length)", field="--thickness"
            )
        result = fit_chromophores(
            args.host,
            target_lab=target,
            illuminant=args.illuminant,
            thickness_mm=args.thickness,
            **common,
        )
    print(result.summary())
    return 0


def run(args) -> int:
    from .. import materials

    if args.name == "fit":
        return _fit(args)
    given = [o for o in _FIT_OPTIONS if getattr(args, o) not in (None, False, "mean")]
    if args.host or given:
        raise InputError(
            "these options belong to `warpoptics material fit HOST ...`",
            field=", ".join((["HOST"] if args.host else []) + [f"--{o.replace('_', '-')}" for o in given]),
        )
    mat = materials.get(args.name)
    if args.plot:
        from ..film.image import FIGURE_FORMATS

        ext = args.plot.rsplit(".", 1)[-1].lower() if "." in args.plot else "png"
        if ext not in FIGURE_FORMATS:
            raise InputError(
                "unsupported plot format",
                field="--plot",
                value=args.plot,
                allowed=", ".join(f".{f}" for f in FIGURE_FORMATS),
            )
    print("\n".join(_summary(mat)))
    if args.plot:
        _plot(mat, args.plot)
        print(f"plot           {args.plot}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "material", help="print a library material's indices, dispersion and source; plot n and alpha"
    )
    p.add_argument(
        "name", help='library name, e.g. "diamond", "sapphire", "rose_bengal_10"; or "fit" (see below)'
    )
    p.add_argument("host", nargs="?", default=None, help="fit: the host crystal, e.g. quartz, tourmaline")
    p.add_argument(
        "--plot",
        metavar="FILE",
        default=None,
        help="write a plot of n(λ) and alpha(λ) (PNG); biaxial: n_alpha/beta/gamma, 2V(λ), alpha_X/Y/Z",
    )
    f = p.add_argument_group(
        "fit",
        "warpoptics material fit HOST --spectrum FILE.csv [...] | --lab L,a,b --thickness MM [...]: "
        "non-negative chromophore concentrations that reproduce a measured spectrum or a colour "
        "(a cut stone enters a colour fit only as its effective path length --thickness)",
    )
    f.add_argument("--spectrum", default=None, help="CSV: wavelength (nm), value (# comments, one header)")
    f.add_argument(
        "--quantity",
        default="absorbance",
        choices=("absorbance", "alpha_per_mm", "alpha_per_cm"),
        help="what the CSV's values are (absorbance: decadic, needs --path-mm; default absorbance)",
    )
    f.add_argument("--path-mm", type=float, default=None, help="path length of the absorbance (mm)")
    f.add_argument(
        "--polarization", default="mean", help="the host polarization measured (o, e, x, y, z) or mean"
    )
    f.add_argument("--baseline", action="store_true", help="also fit a flat baseline (1/mm)")
    f.add_argument("--range", default="400,700", help="wavelength window of the fit, nm (default 400,700)")
    f.add_argument("--lab", default=None, help="target CIELAB L,a,b")
    f.add_argument("--illuminant", default="D65", help="light of the target colour (default D65)")
    f.add_argument("--thickness", type=float, default=None, help="plate thickness / path length (mm)")
    f.add_argument("--chromophores", default=None, help="fit only these, comma-separated (default all)")
    p.set_defaults(func=run)
