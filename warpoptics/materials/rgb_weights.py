"""The weights of Guy & Soler 2004 eq. 9: κ_c = ∫ κ(λ) c̄(λ) S0(λ) dλ / ∫ c̄(λ) S0(λ) dλ as a
quadrature Σ_j w_cj κ(λ_j), for the CIE 1931 RGB or the linear-sRGB colour-matching functions.
Below the material modules: it knows colour-matching functions and illuminants, not materials.

References
----------
- S. Guy, C. Soler, "Graphics gems revisited", ACM TOG 23(3), 2004, eq. 9.
- W. D. Wright (1928), J. Guild (1931): CIE 1931 2° RGB colour matching functions (primaries
  700, 546.1, 435.8 nm), as tabulated in colour-science ("Wright & Guild 1931 2 Degree RGB CMFs").
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["RGB_CMFS", "rgb_weights"]

_CMF_NAME = "Wright & Guild 1931 2 Degree RGB CMFs"
#: colour-matching functions for eq. 9: "cie1931_rgb" (Wright & Guild, primaries 700 / 546.1 /
#: 435.8 nm, as in the source) or "srgb" (the CIE 1931 XYZ functions through XYZ -> linear sRGB:
#: the channels of the renderer's rgb3 mode, warpoptics.spectra.RGB3_WAVELENGTHS)
RGB_CMFS = ("cie1931_rgb", "srgb")
_cmf_cache: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]] = {}


def rgb_weights(illuminant: str = "E", cmfs: str = "cie1931_rgb") -> tuple[np.ndarray, np.ndarray]:
    """(λ nodes, weights (3, m)) with κ_c = Σ_j w_cj κ(λ_j) = eq. 9 by trapezoid quadrature."""
    key = (illuminant, cmfs)
    if key in _cmf_cache:
        return _cmf_cache[key]
    from .. import spectra

    if cmfs == "cie1931_rgb":
        import colour  # heavy import: only when needed

        table = colour.MSDS_CMFS[_CMF_NAME]
        lam = np.asarray(table.wavelengths, dtype=np.float64)  # 380-780 nm, 5 nm
        rgb = np.asarray(table.values, dtype=np.float64).T  # (3, m)
    elif cmfs == "srgb":
        from ..color import XYZ_TO_SRGB

        lam = spectra.grid()  # 360-830 nm, 1 nm
        rgb = XYZ_TO_SRGB @ spectra.cmf(lam).T  # (3, m)
    else:
        raise InputError(
            "unknown colour-matching functions", field="cmfs", value=cmfs, allowed=", ".join(RGB_CMFS)
        )
    try:
        s0 = spectra.illuminant(illuminant, lam)
    except ValueError as exc:
        raise InputError(
            "unknown illuminant", field="illuminant", value=illuminant, allowed=", ".join(spectra.ILLUMINANTS)
        ) from exc
    q = np.full_like(lam, lam[1] - lam[0])  # trapezoid weights on the uniform grid
    q[0] *= 0.5
    q[-1] *= 0.5
    w = rgb * s0 * q
    w = w / w.sum(axis=1, keepdims=True)  # divide by R0 = ∫ r̄ S0 dλ (eq. 9)
    _cmf_cache[key] = (lam, w)
    return lam, w
