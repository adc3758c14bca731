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

- **Absorption per wave in a biaxial crystal** (trichroism): :func:`trichroic_kappa`.  A wave
  absorbs by what its own *D* vibration sees.  To first order in the absorption the impermeability
  of an absorbing crystal is eps^-1 = diag(1/N_i^2) with N_i = n_i (1 + i kappa_i), and a wave of
  unit D direction d has 1/N^2 = d . eps^-1 . d (Born & Wolf 1999 §15.6, eq. 9-12: the index
  ellipsoid of an absorbing crystal), i.e. kappa / n^2 = sum_i d_i^2 kappa_i / n_i^2.  Guy &
  Soler's eq. 7 is this law for a uniaxial crystal written with the reference index n_o in place of
  the wave's own n (they drop the factor (n/n_o)^2 = 1 + O(birefringence)) and the principal
  absorbances K_i in place of kappa_i: kappa = sum_i K_i (n_o / n_i)^2 d_i^2.  We keep eq. 7's form
  with n_beta as the reference index, which is n_o in both uniaxial limits (n_alpha = n_beta or
  n_beta = n_gamma), so a biaxial medium with two equal indices gives exactly eq. 7:

      kappa = sum_i alpha_i (n_beta / n_i)^2 d_i^2      (d in principal coordinates).

  D rather than E: D is transverse (d . s = 0, so the three weights sum to at most 1 and a wave
  along a principal axis sees only the two other spectra — the measured "principal spectra" of a
  trichroic stone are taken with light polarized along an axis), and it is the vector of eq. 7
  (D^o along X_a, D^e along Y_a of eq. 2).  For D along a principal axis i the law gives
  alpha_i (n_beta/n_i)^2 — alpha_i itself for Y, and alpha_i within (n_gamma/n_alpha)^2 - 1
  (< 2 % for the library's stones) for X and Z, as eq. 7 does for e-waves.
"""

from __future__ import annotations

import warp as wp

from .jones import jones_real

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "bouguer_lambert",
    "bouguer_lambert_integral",
    "sample_bouguer_lambert_distance",
    "pleochroic_kappa",
    "trichroic_kappa",
    "wave_kappa",
    "attenuation_oe",
]


@wp.func
def bouguer_lambert(alpha: float, length: float):
    """Transmitted fraction exp(-alpha l) of the intensity over ``length`` mm (alpha in 1/mm)."""
    return wp.exp(-alpha * length)


@wp.func
def bouguer_lambert_integral(alpha: float, length: float):
    """Integral over the path of the transmitted fraction, int_0^l exp(-alpha s) ds =
    (1 - exp(-alpha l)) / alpha (mm; ``length`` for alpha -> 0): the weight of a source spread
    evenly along a segment (a fluorescent emission) seen from its start."""
    x = alpha * length
    if wp.abs(x) < 1.0e-3:
        return length * (1.0 - 0.5 * x + x * x / 6.0)
    return (1.0 - wp.exp(-x)) / alpha


@wp.func
def sample_bouguer_lambert_distance(alpha: float, length: float, u: float):
    """A distance s in [0, ``length``] drawn with density exp(-alpha s) /
    :func:`bouguer_lambert_integral` (the truncated exponential, by inversion; uniform for
    alpha -> 0) from uniform ``u`` in [0, 1)."""
    x = alpha * length
    if wp.abs(x) < 1.0e-3:
        return u * length
    s = -wp.log(1.0 - u * (1.0 - wp.exp(-x))) / alpha
    return wp.clamp(s, 0.0, length)


@wp.func
def pleochroic_kappa(cos_theta: float, k_o: float, k_e: float, no: float, ne: float):
    """kappa^e = K^o cos^2 theta + K^e (n_o/n_e)^2 sin^2 theta (Guy & Soler 2004 eq. 7), with
    cos theta = wave normal . optic axis; units those of K^o, K^e."""
    c2 = wp.min(cos_theta * cos_theta, 1.0)
    r = no / ne
    return k_o * c2 + k_e * r * r * (1.0 - c2)


@wp.func
def trichroic_kappa(d: wp.vec3, n3: wp.vec3, alpha3: wp.vec3):
    """kappa = sum_i alpha_i (n_beta / n_i)^2 d_i^2 of a wave with unit D ``d`` (principal
    coordinates) in a crystal of principal indices ``n3`` = (n_alpha, n_beta, n_gamma) and
    principal absorption coefficients ``alpha3`` (module docstring; eq. 7 when two n_i coincide)."""
    k = float(0.0)
    for i in range(3):
        r = n3[1] / n3[i]
        k += alpha3[i] * r * r * d[i] * d[i]
    return k


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
