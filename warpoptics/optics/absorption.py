"""Absorption along a ray: Bouguer–Lambert attenuation and the absorption each wave sees.

The one place of these laws; the tracers (camera, bench, caustics, shadow rays) and the NumPy
wrappers (``warpoptics.materials.pleochroic_alpha``, ``warpoptics.optics.kappa_e`` and
``attenuation``) call these ``@wp.func``\\ s.

- **Bouguer–Lambert** (Weidlich & Wilkie 2009 eq. 3; Guy & Soler 2004 eq. 6): the intensity of
  a ray falls as exp(-alpha l) over a path length l (mm) with the base-e absorption coefficient
  alpha (1/mm) = 4 pi k / lambda.
- **Absorption per wave in a uniaxial crystal** (Guy & Soler 2004 eq. 7, after Born & Wolf
  §15.6): the o-wave absorbs with K^o; an e-wave whose wave normal makes the angle theta with the
  optic axis absorbs with kappa^e = K^o cos^2 theta + K^e (n_o / n_e)^2 sin^2 theta.
- **The o/e attenuation matrix** (eq. 11): diag(exp(-kappa_o l / 2), exp(-kappa_e l / 2)) on
  the field, so that A J A^dagger follows the intensity law.

A new kind of medium (biaxial, three principal absorptions) adds its per-wave law here, beside
``pleochroic_kappa``, and the media layer (``stages/media.py``) chooses it per wave.
"""

from __future__ import annotations

import warp as wp

from .jones import jones_real

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["bouguer_lambert", "pleochroic_kappa", "wave_kappa", "attenuation_oe"]


@wp.func
def bouguer_lambert(alpha: float, length: float):
    """Transmitted fraction exp(-alpha l) of the intensity over ``length`` mm (alpha in 1/mm)."""
    return wp.exp(-alpha * length)


@wp.func
def pleochroic_kappa(cos_theta: float, k_o: float, k_e: float, no: float, ne: float):
    """kappa^e = K^o cos^2 theta + K^e (n_o/n_e)^2 sin^2 theta (Guy & Soler 2004 eq. 7), with
    cos theta = wave normal . optic axis; units those of K^o, K^e."""
    c2 = wp.min(cos_theta * cos_theta, 1.0)
    r = no / ne
    return k_o * c2 + k_e * r * r * (1.0 - c2)


@wp.func
def wave_kappa(mode: int, cos_theta: float, k_o: float, k_e: float, no: float, ne: float):
    """Absorption coefficient of one wave: K^o for an isotropic (mode -1) or ordinary (0) wave,
    :func:`pleochroic_kappa` for an extraordinary wave (mode 1)."""
    if mode == 1:
        return pleochroic_kappa(cos_theta, k_o, k_e, no, ne)
    return k_o


@wp.func
def attenuation_oe(kappa_o: float, kappa_e: float, length: float):
    """Field attenuation A = diag(exp(-kappa_o l/2), exp(-kappa_e l/2)) in the o/e frame (eq. 11
    with the 1/2 that makes A J A^dagger follow the intensity law exp(-kappa l) of eq. 6)."""
    return jones_real(wp.mat22(wp.exp(-0.5 * kappa_o * length), 0.0, 0.0, wp.exp(-0.5 * kappa_e * length)))
