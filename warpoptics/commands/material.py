"""`warpoptics material NAME [--plot FILE]`: a library material's optical constants."""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def _summary(mat) -> list[str]:
    from ..materials import Uniaxial, abbe_number, dispersion_bg, rgb3_alpha_of

    lo, hi = mat.wavelength_range_nm
    lines = [f"material       {mat.name}"]
    lines.append(f"type           {'uniaxial' if isinstance(mat, Uniaxial) else 'isotropic'}")
    lines.append(f"range          {lo:g}-{hi:g} nm")
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


def _plot(mat, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..film.image import save_figure
    from ..materials import Uniaxial

    lo, hi = mat.wavelength_range_nm
    lam = np.linspace(max(lo, 360.0), min(hi, 830.0), 471)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    if isinstance(mat, Uniaxial):
        n, alpha = mat.n(lam), mat.alpha(lam)
        a1.plot(lam, n[:, 0], label="n_o")
        a1.plot(lam, n[:, 1], label="n_e")
        a2.plot(lam, alpha[:, 0], label="alpha_o")
        a2.plot(lam, alpha[:, 1], label="alpha_e")
    else:
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
    save_figure(fig, path, field="--plot", dpi=100)
    plt.close(fig)


def run(args) -> int:
    from .. import materials

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
    p.add_argument("name", help='library name, e.g. "diamond", "sapphire", "rose_bengal_10"')
    p.add_argument("--plot", metavar="FILE", default=None, help="write a plot of n(λ) and alpha(λ) (PNG)")
    p.set_defaults(func=run)
