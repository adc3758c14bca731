"""Closed-form plane stress fields of glass parts, for photoelastic images.

- :func:`brazilian_disc`: a disc of diameter D and thickness t compressed by two equal and
  opposite forces P along a diameter (the "Brazilian" test; H. Hertz 1883, A. Föppl; Frocht
  1948, Photoelasticity vol. 2; Timoshenko & Goodier 1970, Theory of Elasticity §41):
  the superposition of two Flamant radial fields from the load points and a uniform tension
  2P / (pi D t) that frees the rim of traction,
      sigma_xx = -(2P / pi t) [x^2 (R - y) / r1^4 + x^2 (R + y) / r2^4 - 1 / D]
      sigma_yy = -(2P / pi t) [(R - y)^3 / r1^4 + (R + y)^3 / r2^4 - 1 / D]
      tau_xy   =  (2P / pi t) [x (R - y)^2 / r1^4 - x (R + y)^2 / r2^4]
  with the loads at (0, +-R), r1^2 = x^2 + (R - y)^2, r2^2 = x^2 + (R + y)^2.  At the centre
  sigma_1 - sigma_2 = 8P / (pi D t); along the loaded diameter 8 P D / (pi t (D^2 - 4 y^2)).
- :func:`quenched_plate`: the residual stress of a glass plate cooled from both faces
  (thermal tempering; Adams & Williamson 1920; Gardon 1980): parabolic through the thickness,
  compression at the faces, tension inside, in-plane isotropic; seen edge-on (light along the
  plate, across its thickness z) the stress is uniaxial along the viewing-plane axis, and a
  well-annealed plate (zero stress) is the strain-free reference.

Units: N, mm, MPa (N/mm^2).  The fields are mechanics inputs to ``optics.photoelastic``, not
optical laws; they are evaluated in NumPy.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["STRESS_OPTIC_TPA", "brazilian_disc", "quenched_plate"]

#: stress-optic coefficients C (TPa^-1 = 1e-12 / Pa, at 589.3 nm, 21 C): SCHOTT N-BK7 data sheet
#: ("stress optical coefficient K = 2.77 x 10^-6 mm^2/N")
STRESS_OPTIC_TPA = {"bk7": 2.77}


def _positive(v, name: str) -> float:
    if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
        raise InputError("must be a number > 0", field=name, value=v, allowed="> 0")
    return float(v)


def brazilian_disc(x_mm, y_mm, *, diameter_mm: float, thickness_mm: float, load_n: float):
    """(sigma_xx, sigma_yy, tau_xy) in MPa at points (x, y) (mm, disc centre at the origin,
    loads at (0, +-D/2) along y); NaN outside the disc and at the load points."""
    d = _positive(diameter_mm, "diameter_mm")
    t = _positive(thickness_mm, "thickness_mm")
    p = float(load_n)
    if not np.isfinite(p):
        raise InputError("must be finite", field="load_n", value=load_n)
    x = np.asarray(x_mm, dtype=np.float64)
    y = np.asarray(y_mm, dtype=np.float64)
    r = 0.5 * d
    a = r - y
    b = r + y
    r1 = (x**2 + a**2) ** 2
    r2 = (x**2 + b**2) ** 2
    inside = (x**2 + y**2 <= r * r) & (r1 > 0) & (r2 > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = 2.0 * p / (np.pi * t)
        sxx = -k * (x**2 * a / r1 + x**2 * b / r2 - 1.0 / d)
        syy = -k * (a**3 / r1 + b**3 / r2 - 1.0 / d)
        txy = k * (x * a**2 / r1 - x * b**2 / r2)
    nan = np.where(inside, 0.0, np.nan)
    return sxx + nan, syy + nan, txy + nan


def quenched_plate(z_mm, *, thickness_mm: float, surface_mpa: float):
    """In-plane residual stress (MPa) at depth ``z`` (mm, 0 at mid-plane) of a plate of
    ``thickness_mm`` tempered by quenching: sigma(z) = -s (3 (2z / h)^2 - 1) / 2 with the
    surface compression ``surface_mpa`` = s >= 0 (sigma(+-h/2) = -s, sigma(0) = s / 2; zero
    net force).  ``surface_mpa = 0``: annealed."""
    h = _positive(thickness_mm, "thickness_mm")
    if not (isinstance(surface_mpa, (int, float)) and np.isfinite(surface_mpa) and surface_mpa >= 0):
        raise InputError("must be a number >= 0", field="surface_mpa", value=surface_mpa, allowed=">= 0")
    u = 2.0 * np.asarray(z_mm, dtype=np.float64) / h
    return np.where(np.abs(u) <= 1.0, -float(surface_mpa) * 0.5 * (3.0 * u**2 - 1.0), np.nan)
