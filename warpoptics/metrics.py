"""Image metrics of rendered stones: colour, colour differences and gem light performance.

Every metric works on the renderer's linear outputs (``Image.xyz``, ``Image.alpha``), never on
tone-mapped pixels.  XYZ is relative: Y = 1 is a white at the lighting's unit intensity (a
``dome`` of intensity 1 seen directly), and CIELAB uses the D65 white with Y = 1.  "The stone's
pixels" are weighted by the image alpha, the fraction of a pixel's primary rays that hit an
object.

- :func:`mean_color` — alpha-weighted mean XYZ, CIELAB L*, a*, b*, chroma and hue.
- :func:`delta_e_image`, :func:`delta_e_stats`, :func:`delta_e_mean_color` — CIEDE2000 between
  paired renders; :func:`difference_image` turns a ΔE map into a false-colour picture.
- :func:`light_return` — brightness, after GIA's *weighted light return* (WLR): alpha-weighted
  mean luminance of a face-up view under the ``dome``, relative to the dome's.
- :func:`fire` — after GIA's *dispersed coloured light return* (DCLR): alpha-weighted mean of
  luminance x CIE 1976 u'v' saturation under a small bright source.
- :func:`scintillation` — luminance-weighted Michelson contrast between a view and the stone
  tilted a little: 0 when nothing changes, 1 when all the light moves to other pixels.
- :func:`colour_change` — hue-angle change and CIEDE2000 of a spectrum between two illuminants
  (the alexandrite effect); :func:`plate_transmittance` gives a polished plate's spectrum.

The gem metrics follow GIA's computer-model metrics in spirit, with one image-based view
instead of all exit directions; where and why they differ: docs/design/grading_metrics.md.

References: Hemphill et al., Gems & Gemology 34(3) 1998 (brilliance); Reinitz et al., G&G 37(3)
2001 (fire); Moses et al., G&G 40(3) 2004 (cut grading); CIE 15:2004 §8.1 (u'v' saturation);
CIE 142-2001 (CIEDE2000).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from . import color
from .errors import InputError
from .materials.plate import plate_transmittance

__all__ = [
    "D65_WHITE_XYZ",
    "mean_color",
    "delta_e_image",
    "delta_e_stats",
    "delta_e_mean_color",
    "difference_image",
    "uv_prime",
    "saturation_uv",
    "light_return",
    "fire",
    "scintillation",
    "plate_transmittance",
    "colour_change",
]

# D65 white with Y = 1 (CIE 1931 2 degree chromaticity x = 0.31270, y = 0.32900)
D65_WHITE_XYZ = np.array([0.31270 / 0.32900, 1.0, (1.0 - 0.31270 - 0.32900) / 0.32900])


def _xyz_alpha(xyz, alpha) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(xyz, dtype=np.float64)
    if x.ndim < 1 or x.shape[-1] != 3:
        raise InputError(
            "an XYZ image must have shape (..., 3)", field="xyz", value=getattr(x, "shape", None)
        )
    if alpha is None:
        a = np.ones(x.shape[:-1])
    else:
        a = np.asarray(alpha, dtype=np.float64)
        if a.shape != x.shape[:-1]:
            raise InputError(
                "alpha must have the image's shape without the colour axis",
                field="alpha",
                value=a.shape,
                allowed=str(x.shape[:-1]),
            )
    if not (np.isfinite(x).all() and np.isfinite(a).all()):
        raise InputError("the image has non-finite pixels", field="xyz")
    if (a < 0).any():
        raise InputError("alpha must be >= 0", field="alpha")
    return x, a


def _weighted_mean_xyz(x: np.ndarray, a: np.ndarray) -> np.ndarray:
    w = a.sum()
    if w <= 0:
        return np.zeros(3)
    return (x * a[..., None]).reshape(-1, 3).sum(axis=0) / w


def mean_color(xyz, alpha=None, *, white_xyz=None) -> dict[str, float]:
    """Mean colour of the stone's pixels.

    ``X, Y, Z`` = Σ_p α_p XYZ_p / Σ_p α_p (α = image alpha, default 1 everywhere); then
    ``L, a, b`` = CIELAB of that mean (white ``white_xyz``, default D65 with Y = 1), chroma
    ``C`` = sqrt(a² + b²) and hue angle ``h`` = atan2(b, a) in degrees [0, 360); ``coverage``
    = Σ α / number of pixels.  An image without stone pixels gives zeros (and L = 0).
    """
    x, a = _xyz_alpha(xyz, alpha)
    m = _weighted_mean_xyz(x, a)
    lab = color.xyz_to_lab(m, white_xyz)
    c = float(math.hypot(lab[1], lab[2]))
    h = float(math.degrees(math.atan2(lab[2], lab[1])) % 360.0) if c > 0 else 0.0
    return {
        "X": float(m[0]),
        "Y": float(m[1]),
        "Z": float(m[2]),
        "L": float(lab[0]),
        "a": float(lab[1]),
        "b": float(lab[2]),
        "C": c,
        "h": h,
        "coverage": float(a.sum() / max(a.size, 1)),
    }


def delta_e_image(xyz_a, xyz_b, *, white_xyz=None) -> np.ndarray:
    """Per-pixel CIEDE2000 difference between two XYZ images of the same shape (..., 3)."""
    a = np.asarray(xyz_a, dtype=np.float64)
    b = np.asarray(xyz_b, dtype=np.float64)
    if a.shape != b.shape or a.shape[-1:] != (3,):
        raise InputError(
            "the two images must have the same shape (..., 3)", field="xyz", value=(a.shape, b.shape)
        )
    return np.asarray(color.delta_e2000(a, b, white_xyz), dtype=np.float64)


def delta_e_stats(delta_e, alpha_a=None, alpha_b=None) -> dict[str, float]:
    """Statistics of a ΔE map over the stone's pixels in either image.

    Weights w_p = max(α_a, α_b) (the union of the two silhouettes; 1 everywhere without alphas).
    ``dE_mean`` = Σ w ΔE / Σ w; ``dE_p95`` = 95th percentile of ΔE over pixels with w >= 0.5;
    ``dE_max`` = largest ΔE over pixels with w > 0.
    """
    d = np.asarray(delta_e, dtype=np.float64)
    w = np.ones_like(d)
    if alpha_a is not None or alpha_b is not None:
        wa = np.zeros_like(d) if alpha_a is None else np.asarray(alpha_a, dtype=np.float64)
        wb = np.zeros_like(d) if alpha_b is None else np.asarray(alpha_b, dtype=np.float64)
        w = np.maximum(wa, wb)
    if w.shape != d.shape:
        raise InputError("alpha and ΔE maps differ in shape", field="alpha", value=(w.shape, d.shape))
    if w.sum() <= 0:
        return {"dE_mean": 0.0, "dE_p95": 0.0, "dE_max": 0.0}
    inside = d[w >= 0.5]
    return {
        "dE_mean": float((w * d).sum() / w.sum()),
        "dE_p95": float(np.percentile(inside, 95)) if inside.size else 0.0,
        "dE_max": float(d[w > 0].max()),
    }


def delta_e_mean_color(xyz_a, alpha_a, xyz_b, alpha_b, *, white_xyz=None) -> float:
    """CIEDE2000 between the two stones' mean colours (:func:`mean_color`'s X, Y, Z)."""
    xa, aa = _xyz_alpha(xyz_a, alpha_a)
    xb, ab = _xyz_alpha(xyz_b, alpha_b)
    return float(color.delta_e2000(_weighted_mean_xyz(xa, aa), _weighted_mean_xyz(xb, ab), white_xyz))


def difference_image(delta_e, *, scale: float = 10.0, colormap: str = "inferno") -> np.ndarray:
    """False-colour picture (H, W, 3) in [0, 1] of a ΔE map: ΔE / ``scale`` through a matplotlib
    colour map (black = no difference, the top of the map = ``scale`` or more)."""
    from matplotlib import colormaps

    if not scale > 0:
        raise InputError("must be > 0", field="scale", value=scale)
    t = np.clip(np.asarray(delta_e, dtype=np.float64) / scale, 0.0, 1.0)
    return np.asarray(colormaps[colormap](t))[..., :3]


def uv_prime(xyz) -> np.ndarray:
    """CIE 1976 UCS chromaticity (u', v') = (4X, 9Y) / (X + 15Y + 3Z) (CIE 15:2004, eq. 8.8);
    black (X + 15Y + 3Z = 0) maps to the D65 white's chromaticity."""
    x = np.asarray(xyz, dtype=np.float64)
    wx, wy, wz = D65_WHITE_XYZ
    wd = wx + 15 * wy + 3 * wz
    d = x[..., 0] + 15 * x[..., 1] + 3 * x[..., 2]
    ok = d > 0
    safe = np.where(ok, d, 1.0)
    u = np.where(ok, 4 * x[..., 0] / safe, 4 * wx / wd)
    v = np.where(ok, 9 * x[..., 1] / safe, 9 * wy / wd)
    return np.stack([u, v], axis=-1)


def saturation_uv(xyz, reference_uv=None) -> np.ndarray:
    """CIE 1976 u'v' saturation s_uv = 13 sqrt((u' - u'_n)² + (v' - v'_n)²) (CIE 15:2004,
    §8.2.2); the reference (u'_n, v'_n) defaults to the D65 white.  Independent of luminance."""
    uv = uv_prime(xyz)
    ref = uv_prime(D65_WHITE_XYZ) if reference_uv is None else np.asarray(reference_uv, dtype=np.float64)
    return 13.0 * np.sqrt(((uv - ref) ** 2).sum(axis=-1))


def light_return(xyz, alpha=None, *, white_y: float = 1.0) -> float:
    """Light return (brightness) of a face-up view under the standard ``dome`` lighting.

    LR = Σ_p α_p Y_p / (Y_w Σ_p α_p): the stone's alpha-weighted mean luminance relative to the
    luminance ``white_y`` (Y_w) of the dome seen directly.  1 = the stone returns to the viewer
    as much light as the dome sends; a stone whose pavilion leaks light (or a black stone) tends
    to 0.  After GIA's weighted light return (Hemphill et al. 1998); see the module docstring
    for where it differs.
    """
    x, a = _xyz_alpha(xyz, alpha)
    if not white_y > 0:
        raise InputError("must be > 0", field="white_y", value=white_y)
    w = a.sum()
    if w <= 0:
        return 0.0
    return float((a * x[..., 1]).sum() / (white_y * w))


def fire(xyz, alpha=None, *, reference: str = "white", min_saturation: float = 0.0) -> float:
    """Fire (dispersed coloured light) of a face-up view under the standard spot lighting.

    F = Σ_p α_p Y_p s_p [s_p >= s_min] / Σ_p α_p, with s_p the CIE 1976 u'v' saturation of
    pixel p (:func:`saturation_uv`) about the D65 white (``reference="white"``) or about the
    stone's mean chromaticity (``reference="mean"``: the dispersed colour around a coloured
    stone's body colour), and s_min = ``min_saturation``.  Units: luminance (Y) x saturation.
    After GIA's dispersed coloured light return (Reinitz et al. 2001); see the module docstring.
    """
    x, a = _xyz_alpha(xyz, alpha)
    if reference not in ("white", "mean"):
        raise InputError("unknown reference", field="reference", value=reference, allowed="white, mean")
    if not min_saturation >= 0:
        raise InputError("must be >= 0", field="min_saturation", value=min_saturation)
    w = a.sum()
    if w <= 0:
        return 0.0
    ref = uv_prime(_weighted_mean_xyz(x, a)) if reference == "mean" else None
    s = saturation_uv(x, ref)
    s = np.where(s >= min_saturation, s, 0.0)
    return float((a * x[..., 1] * s).sum() / w)


def scintillation(base_xyz, base_alpha, tilted: Sequence[tuple]) -> float:
    """Scintillation: how much of the returned light changes pixel under small tilts.

    For each tilted view k (``tilted`` = [(xyz_k, alpha_k), ...], same camera, the stone rotated
    by a small angle), with weights w_p = min(α_0, α_k) (pixels covered in both views)::

        c_k = Σ_p w_p |Y_k,p - Y_0,p| / Σ_p w_p (Y_k,p + Y_0,p)

    (a luminance-weighted Michelson contrast, in [0, 1]); the metric is the mean of c_k over the
    tilts.  0: the pattern does not change; 1: every bright pixel goes dark and vice versa.
    """
    x0, a0 = _xyz_alpha(base_xyz, base_alpha)
    if len(tilted) == 0:
        raise InputError("scintillation needs at least one tilted view", field="tilts")
    cs = []
    for xk, ak in tilted:
        xk, ak = _xyz_alpha(xk, ak)
        if xk.shape != x0.shape:
            raise InputError(
                "tilted views must have the base view's shape", field="tilts", value=(xk.shape, x0.shape)
            )
        w = np.minimum(a0, ak)
        y0, yk = np.maximum(x0[..., 1], 0.0), np.maximum(xk[..., 1], 0.0)
        den = (w * (y0 + yk)).sum()
        cs.append(float((w * np.abs(yk - y0)).sum() / den) if den > 0 else 0.0)
    return float(np.mean(cs))


def colour_change(
    wavelength_nm, spectrum, *, illuminants: Sequence[str] = ("D65", "A")
) -> dict[str, float | tuple]:
    """Colour change of a transmission (or reflectance) ``spectrum`` at ``wavelength_nm`` (nm,
    increasing; linear in between, zero outside) between two illuminants.

    Under each illuminant S (``spectra.light_spectrum``, Y = 1): XYZ = integral S T cmf / integral
    S ybar over 360-830 nm (CIE 1931 2 degree; 1 nm trapezoid), CIELAB against that illuminant's
    own white (the white object under the same light: no chromatic adaptation, as colour-change
    studies compare the colours seen in each light, e.g. Sun et al., Gems & Gemology 51(4),
    2015), then the hue angles h_ab, their difference |h_1 - h_2| folded into 0-180 degrees
    (0 when either colour is achromatic, C*ab < 1e-6), and CIEDE2000 between the two Lab
    values (CIE 142-2001, colour-science).  Returns ``lab`` (two triples), ``chroma``, ``hue``
    (degrees), ``delta_hue`` and ``delta_e00``.
    """
    import colour

    if len(illuminants) != 2:
        raise InputError("needs two illuminants", field="illuminants", value=list(illuminants))
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    v = np.asarray(spectrum, dtype=np.float64)
    if wl.ndim != 1 or v.shape != wl.shape or wl.size < 2 or np.any(np.diff(wl) <= 0):
        raise InputError(
            "needs >= 2 increasing wavelengths and as many values", field="spectrum", value=v.shape
        )
    if not (np.isfinite(v).all() and v.min() >= 0):
        raise InputError("must be finite and >= 0", field="spectrum")
    labs, hues, chromas = [], [], []
    for name in illuminants:
        lab, _xyz, _white = color.spectrum_lab(wl, v, name)
        labs.append(lab)
        chromas.append(float(np.hypot(lab[1], lab[2])))
        hues.append(float(np.degrees(np.arctan2(lab[2], lab[1])) % 360.0))
    dh = abs(hues[0] - hues[1]) % 360.0
    dh = 360.0 - dh if dh > 180.0 else dh
    if min(chromas) < 1e-6:
        dh = 0.0
    de = float(colour.delta_E(labs[0], labs[1], method="CIE 2000"))
    return {
        "illuminants": tuple(illuminants),
        "lab": tuple(tuple(float(x) for x in lab) for lab in labs),
        "chroma": tuple(chromas),
        "hue": tuple(hues),
        "delta_hue": float(dh),
        "delta_e00": de,
    }
