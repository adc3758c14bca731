"""The Smits & Meyer 1990 interference model against the exact thin-film stack.

Four comparisons, each printed as the largest difference and where it occurs, and plotted:

A. soap film (air | n = 1.33 | air) at normal incidence: eq. 7 with K = 2|r| against the exact
   single film (multiple reflections, the paper's model keeps two beams);
B. a film without the phase change (air | 1.33 | sapphire 1.77): eq. 8 with K = |r01| + |r12|;
C. the angle rule at 60 degrees: eq. 11 (t' = t n cos(theta) with the viewing angle, as the paper
   applies it) and the refraction-angle phase t (n^2 - sin^2 theta)^(1/2) (eq. 10), both against
   the exact unpolarized reflectance;
D. the Morpho multilayer (twelve mullions n = 1.53, d2 = 50 nm, air gaps d1 = 150 nm): the peak
   wavelength of eq. 9 with eq. 14 against the exact stack's reflectance peak, over angles, and
   the colour difference (CIEDE2000) of the two tables, each scaled to the same peak luminance.

Colour differences for A and B use one exposure for both models (the exact table's brightest
entry at Y = 1).

    python scripts/reproduce/smits_meyer_model_vs_exact.py -o model_vs_exact.png [--quick]
"""

from __future__ import annotations

import argparse

import numpy as np

import warpoptics as wo
from warpoptics.color import delta_e2000


def _largest(label: str, diff: np.ndarray, where: str, fmt: str = ".4f") -> str:
    return f"{label:58s} {diff:{fmt}}  at {where}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="figure path (.png/.pdf/.svg)")
    ap.add_argument("--quick", action="store_true", help="coarse sampling (for tests)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    tf = wo.thinfilm
    dev = args.device
    nt = 41 if args.quick else 501
    nw = 21 if args.quick else 201
    wl = np.linspace(380.0, 780.0, nw)
    t = np.linspace(0.0, 1000.0, nt)
    # thickness arrays go to the exact stack with a trailing layer axis (one layer)
    W, T = np.meshgrid(wl, t, indexing="ij")
    lines = []

    # A. soap film, phase change
    n = 1.33
    r01 = abs((1.0 - n) / (1.0 + n))
    exact_a = tf.reflectance(W, n, T[..., None], 1.0, 1.0, 0.0, device=dev)
    model_a = tf.smits_meyer_film(W, T * n, True, 2 * r01, device=dev)
    d = np.abs(exact_a - model_a)
    i = np.unravel_index(np.argmax(d), d.shape)
    lines.append(
        _largest("A  soap film, eq. 7 vs exact: max |dR|", d[i], f"{W[i]:.0f} nm, t = {T[i]:.0f} nm")
    )
    lines.append(f"{'':58s} (peak R exact {exact_a.max():.4f}, model {model_a.max():.4f})")

    # B. no phase change: air | 1.33 | 1.77
    ns = 1.77
    r12 = abs((n - ns) / (n + ns))
    exact_b = tf.reflectance(W, n, T[..., None], 1.0, ns, 0.0, device=dev)
    model_b = tf.smits_meyer_film(W, T * n, False, r01 + r12, device=dev)
    d = np.abs(exact_b - model_b)
    i = np.unravel_index(np.argmax(d), d.shape)
    lines.append(
        _largest("B  film on sapphire, eq. 8 vs exact: max |dR|", d[i], f"{W[i]:.0f} nm, t = {T[i]:.0f} nm")
    )

    # colour differences of the tables (A and B), one exposure for both models
    count = 41 if args.quick else 301
    for label, pc, k in (("A", True, 2 * r01), ("B", False, r01 + r12)):
        ex = tf.film_color_table(
            phase_change=pc, model="exact", max_optical_thickness_nm=1330.0, count=count, device=dev
        )
        sm = tf.film_color_table(
            phase_change=pc,
            model="smits-meyer",
            K=k,
            max_optical_thickness_nm=1330.0,
            count=count,
            device=dev,
        )
        de = delta_e2000(ex.xyz * ex.exposure, sm.xyz * ex.exposure)
        j = int(np.argmax(de))
        lines.append(
            _largest(
                f"{label}  colour table, CIEDE2000 model vs exact: max dE",
                de[j],
                f"t' = {ex.axis[j]:.0f} nm (mean dE {de.mean():.2f})",
                ".2f",
            )
        )

    # C. angle rule at 60 degrees
    ang = 60.0
    th = np.radians(ang)
    exact_c = tf.reflectance(W, n, T[..., None], 1.0, 1.0, ang, device=dev)
    rs = (np.cos(th) - np.sqrt(n**2 - np.sin(th) ** 2)) / (np.cos(th) + np.sqrt(n**2 - np.sin(th) ** 2))
    ct = np.sqrt(n**2 - np.sin(th) ** 2) / n
    rp = (n * np.cos(th) - ct) / (n * np.cos(th) + ct)
    k_c = 2.0 * np.sqrt(0.5 * (rs**2 + rp**2))
    tp11 = tf.smits_meyer_optical_thickness(T, n, ang, device=dev)
    tp10 = tf.smits_meyer_effective_thickness(T, n, ang, device=dev)
    model_c11 = tf.smits_meyer_film(W, tp11, True, k_c, device=dev)
    model_c10 = tf.smits_meyer_film(W, tp10, True, k_c, device=dev)
    for label, m in (("eq. 11 (viewing angle)", model_c11), ("eq. 10 (refraction angle)", model_c10)):
        d = np.abs(exact_c - m)
        i = np.unravel_index(np.argmax(d), d.shape)
        lines.append(
            _largest(f"C  60 deg, {label} vs exact: max |dR|", d[i], f"{W[i]:.0f} nm, t = {T[i]:.0f} nm")
        )
    lines.append(
        f"{'':58s} (t' ratio eq. 11 / exact phase = cos(theta) n / sqrt(n^2 - sin^2) = "
        f"{np.cos(th) * n / np.sqrt(n**2 - np.sin(th) ** 2):.3f})"
    )

    # D. Morpho multilayer
    angles = np.linspace(0.0, 80.0, 9 if args.quick else 33)
    # search the exact peak down into the ultraviolet (non-dispersive layers), where the first
    # order goes at grazing angles
    wl_d = np.linspace(120.0, 800.0, 137 if args.quick else 1361)
    idx, thick = tf.morpho_stack()
    exact_d = tf.reflectance(wl_d[:, None], idx, thick, 1.0, 1.0, angles[None, :], device=dev)
    t_eff = tf.smits_meyer_morpho_thickness(150.0, 50.0, 1.53, angles, device=dev)
    # first-order peak of the exact stack: its highest reflectance between the second order
    # (lambda = t_theta) and twice the first (lambda = 4 t_theta), i.e. in (1.4, 2.8) t_theta
    peak_exact = np.empty(angles.size)
    for j in range(angles.size):
        win = (wl_d > 1.4 * t_eff[j]) & (wl_d < 2.8 * t_eff[j])
        peak_exact[j] = wl_d[win][np.argmax(exact_d[win, j])]
    peak_model = 2.0 * t_eff  # first order of eq. 9: lambda = 2 t_theta
    dp = np.abs(peak_exact - peak_model)
    j = int(np.nanargmax(dp))
    lines.append(
        _largest(
            "D  Morpho, first-order peak: max |d lambda| (nm)",
            dp[j],
            f"{angles[j]:.0f} deg (exact {peak_exact[j]:.0f}, model {peak_model[j]:.0f} nm)",
            ".1f",
        )
    )
    lines.append(f"{'':58s} (exact peak R at 0 deg {exact_d[:, 0].max():.3f}; eq. 9 peak = A0 (l+1)^2 / 2)")
    cnt = 9 if args.quick else 90
    ex = tf.multilayer_color_table(model="exact", count=cnt, device=dev, peak_luminance=0.5)
    sm = tf.multilayer_color_table(model="smits-meyer", count=cnt, device=dev, peak_luminance=0.5)
    de = delta_e2000(ex.xyz * ex.exposure, sm.xyz * sm.exposure)
    j = int(np.argmax(de))
    lines.append(
        _largest(
            "D  Morpho colour table, CIEDE2000 (each peak Y = 0.5): max dE",
            de[j],
            f"{ex.axis[j]:.0f} deg (dE at 0 deg {de[0]:.1f})",
            ".1f",
        )
    )

    print("Smits & Meyer 1990 model vs exact thin-film optics: largest differences")
    for line in lines:
        print("  " + line)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.film.image import atomic_path

    k550 = int(np.argmin(np.abs(wl - 550.0)))
    fig, ax = plt.subplots(2, 2, figsize=(10, 7))
    a = ax[0, 0]
    a.plot(t, exact_a[k550], label="exact (air | 1.33 | air)")
    a.plot(t, model_a[k550], "--", label="eq. 7, K = 2|r|")
    a.set(title="A: soap film, 550 nm, normal incidence", xlabel="film thickness t (nm)", ylabel="R")
    a.legend(fontsize=8)
    a = ax[0, 1]
    a.plot(t, exact_b[k550], label="exact (air | 1.33 | 1.77)")
    a.plot(t, model_b[k550], "--", label="eq. 8, K = |r01| + |r12|")
    a.set(title="B: film without phase change, 550 nm", xlabel="film thickness t (nm)", ylabel="R")
    a.legend(fontsize=8)
    a = ax[1, 0]
    a.plot(t, exact_c[k550], label="exact, unpolarized")
    a.plot(t, model_c11[k550], "--", label="eq. 7 with t' = t n cos θ (eq. 11)")
    a.plot(t, model_c10[k550], ":", label="eq. 7 with t (n² − sin²θ)^½ (eq. 10)")
    a.set(title="C: soap film at 60°, 550 nm", xlabel="film thickness t (nm)", ylabel="R")
    a.legend(fontsize=8)
    a = ax[1, 1]
    a.plot(angles, peak_exact, "o-", ms=3, label="exact stack: reflectance peak")
    a.plot(angles, peak_model, "--", label="eq. 9 + 14: λ = 2 t_θ")
    a.set(title="D: Morpho, 12 mullions", xlabel="angle of incidence (deg)", ylabel="first-order peak (nm)")
    a.legend(fontsize=8)
    fig.tight_layout()
    suffix = str(args.output).rsplit(".", 1)[-1].lower() if "." in str(args.output) else "png"
    with atomic_path(args.output) as tmp:
        fig.savefig(tmp, dpi=100, format=suffix)
    plt.close(fig)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
