"""Colour: XYZ <-> linear sRGB, Smits–Meyer gamut clipping, tone mapping, colour differences.

- XYZ <-> linear sRGB (D65 white, IEC 61966-2-1) with the matrices of colour-science.
- Out-of-gamut clipping after Smits & Meyer 1990, "Newton's Colors", §3.2: hold the luminance Y,
  move the colour along the line toward the grey of the same Y on the neutral diagonal, and stop
  at the furthest intersection with the planes of the RGB parallelepiped that the colour lies
  outside of (a Cohen–Sutherland-like test per plane pair).  Since XYZ -> RGB is linear the walk
  is done in RGB, where the gamut planes are R, G, B = 0 and = ``max_value``.
- Tone mapping: exposure, Reinhard or a filmic curve (Narkowicz's ACES fit), then the sRGB
  transfer function from colour-science.
- CIEDE2000 colour difference from colour-science.
- CIELAB of a transmission or reflectance spectrum under a named light (:func:`spectrum_lab`).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from .device import device_function, elementwise
from .errors import InputError

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "SRGB_TO_XYZ",
    "XYZ_TO_SRGB",
    "xyz_to_srgb_linear",
    "srgb_linear_to_xyz",
    "xyz_to_rgb",
    "gamut_clip_smits_meyer",
    "gamut_clip",
    "clip_naive",
    "tone_map",
    "encode_srgb",
    "delta_e2000",
    "xyz_to_lab",
    "spectrum_lab",
]


# The normalised primary matrix of sRGB (IEC 61966-2-1 primaries, D65 white point x = 0.3127,
# y = 0.3290), as colour.normalised_primary_matrix computes it (tests/test_color.py checks it),
# and its exact inverse.  colour's stored XYZ->RGB matrix is the IEC one rounded to 4 decimals,
# which would make the round trip, and so the Y held by the gamut clip, off by 5e-5.  Kept as
# numbers so that importing warpoptics does not import colour-science.
SRGB_TO_XYZ = np.array(
    [
        [0.41239079926595934, 0.35758433938387796, 0.1804807884018343],
        [0.2126390058715103, 0.7151686787677559, 0.07219231536073371],
        [0.01933081871559182, 0.11919477979462595, 0.9505321522496606],
    ]
)
XYZ_TO_SRGB = np.linalg.inv(SRGB_TO_XYZ)

_XYZ_TO_RGB_WP = wp.constant(wp.mat33f(*XYZ_TO_SRGB.astype(np.float32).ravel().tolist()))
# luminance of each linear-sRGB primary: Y = dot(_RGB_LUMINANCE, rgb)
_RGB_LUMINANCE = wp.constant(wp.vec3f(*SRGB_TO_XYZ[1].astype(np.float32).tolist()))


@wp.func
def xyz_to_rgb(xyz: wp.vec3f):
    """CIE XYZ -> linear sRGB (D65).  Y of the sRGB white (1, 1, 1) is 1."""
    return _XYZ_TO_RGB_WP * xyz


@wp.func
def gamut_clip_smits_meyer(xyz: wp.vec3f, max_value: float):
    """Clip an XYZ colour into the linear-sRGB cube [0, max_value]^3, holding Y and moving toward
    the neutral axis (Smits & Meyer 1990, §3.2).  Returns linear sRGB.

    The grey of the same luminance is (Y, Y, Y) in linear sRGB, since the sRGB white has Y = 1.
    Colours whose Y is below 0 map to black, above ``max_value`` to white (their grey point is
    itself outside the gamut).  Use a huge ``max_value`` to clip negative components only (HDR).
    """
    rgb = xyz_to_rgb(xyz)
    y = wp.dot(_RGB_LUMINANCE, rgb)
    if y <= 0.0:
        return wp.vec3f(0.0, 0.0, 0.0)
    if y >= max_value:
        return wp.vec3f(max_value, max_value, max_value)
    grey = wp.vec3f(y, y, y)
    d = grey - rgb
    t = float(0.0)
    for c in range(3):
        if rgb[c] < 0.0:
            t = wp.max(t, -rgb[c] / d[c])  # d[c] > 0 here because grey[c] = y > 0 > rgb[c]
        elif rgb[c] > max_value:
            t = wp.max(t, (max_value - rgb[c]) / d[c])  # d[c] < 0
    out = rgb + d * wp.min(t, 1.0)
    # remove round-off outside the cube
    return wp.vec3f(
        wp.clamp(out[0], 0.0, max_value), wp.clamp(out[1], 0.0, max_value), wp.clamp(out[2], 0.0, max_value)
    )


@wp.kernel
def _gamut_clip_kernel(
    offset: int,
    xyz: wp.array(dtype=wp.vec3f),
    max_value: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    out[i] = gamut_clip_smits_meyer(xyz[i], max_value[i])


def _finite(value, name: str) -> np.ndarray:
    """``value`` as an array, or an InputError naming the argument and its first NaN/Inf."""
    a = np.asarray(value)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


@device_function(gamut_clip_smits_meyer)
def gamut_clip(xyz, max_value=1.0, *, device=None) -> np.ndarray:
    """Smits–Meyer gamut clip of XYZ colours ``(..., 3)`` -> linear sRGB in [0, max_value]."""
    (out,) = elementwise(
        _gamut_clip_kernel,
        [(_finite(xyz, "xyz"), wp.vec3f), (_finite(max_value, "max_value"), wp.float32)],
        [wp.vec3f],
        device=device,
    )
    return out


def xyz_to_srgb_linear(xyz) -> np.ndarray:
    """XYZ ``(..., 3)`` -> linear sRGB, no clipping."""
    return np.asarray(xyz, dtype=np.float64) @ XYZ_TO_SRGB.T


def srgb_linear_to_xyz(rgb) -> np.ndarray:
    """Linear sRGB ``(..., 3)`` -> XYZ."""
    return np.asarray(rgb, dtype=np.float64) @ SRGB_TO_XYZ.T


def clip_naive(xyz, max_value: float = 1.0) -> np.ndarray:
    """Per-channel clipping of linear sRGB, for comparison with :func:`gamut_clip`."""
    return np.clip(xyz_to_srgb_linear(xyz), 0.0, max_value)


def tone_map(rgb, *, exposure: float = 0.0, curve: str = "filmic") -> np.ndarray:
    """Scene-linear RGB -> display-linear RGB in [0, 1].

    ``exposure`` in stops; ``curve`` is "clip" (none), "reinhard" (x / (1 + x)) or "filmic"
    (Narkowicz 2015 fit of the ACES reference rendering transform).
    """
    x = np.maximum(np.asarray(rgb, dtype=np.float64) * 2.0**exposure, 0.0)
    if curve == "clip":
        y = x
    elif curve == "reinhard":
        y = x / (1.0 + x)
    elif curve == "filmic":
        a, b, c, d, e = 2.51, 0.03, 2.43, 0.59, 0.14
        y = (x * (a * x + b)) / (x * (c * x + d) + e)
    else:
        raise ValueError(f"unknown tone curve {curve!r} (allowed: clip, reinhard, filmic)")
    return np.clip(y, 0.0, 1.0)


def encode_srgb(rgb_linear) -> np.ndarray:
    """Display-linear [0, 1] -> sRGB-encoded [0, 1] (IEC 61966-2-1 transfer function)."""
    import colour

    return np.asarray(colour.cctf_encoding(np.clip(rgb_linear, 0.0, 1.0), function="sRGB"))


def xyz_to_lab(xyz, white_xyz=None) -> np.ndarray:
    """CIELAB of XYZ (Y of the white = 1; default white D65)."""
    import colour

    if white_xyz is None:
        white_xy = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    else:
        white_xy = colour.XYZ_to_xy(np.asarray(white_xyz))
    return np.asarray(colour.XYZ_to_Lab(np.asarray(xyz, dtype=np.float64), white_xy))


def delta_e2000(xyz_a, xyz_b, white_xyz=None) -> np.ndarray:
    """CIEDE2000 difference between two XYZ colours / images (Y of the white = 1)."""
    import colour

    return np.asarray(
        colour.delta_E(xyz_to_lab(xyz_a, white_xyz), xyz_to_lab(xyz_b, white_xyz), method="CIE 2000")
    )


def spectrum_lab(wavelength_nm, spectrum, illuminant: str, *, field: str = "illuminants"):
    """CIELAB of a transmission (or reflectance) ``spectrum`` at ``wavelength_nm`` (nm,
    increasing; linear in between, zero outside) seen under the light ``illuminant``
    (``spectra.light_spectrum``): XYZ = integral S T cmf / integral S ybar over 360-830 nm (CIE
    1931 2 degree, 1 nm trapezoid; Y of the white = 1), CIELAB against that light's own white
    (no chromatic adaptation).  Returns ``(lab, xyz, white_xyz)``.  ``field`` names the light in
    errors."""
    import colour

    from .spectra import cmf, grid, light_spectrum

    wl = np.asarray(wavelength_nm, dtype=np.float64)
    v = np.asarray(spectrum, dtype=np.float64)
    g = grid()
    t = np.interp(g, wl, v, left=0.0, right=0.0)
    c = cmf(g)
    s = light_spectrum(illuminant, g)
    norm = np.trapezoid(s * c[:, 1], g)
    if not norm > 0:
        raise InputError("has no visible light (Y = 0)", field=field, value=illuminant)
    xyz = np.trapezoid((s * t)[:, None] * c, g, axis=0) / norm
    white = np.trapezoid(s[:, None] * c, g, axis=0) / norm
    lab = np.asarray(colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(white)))
    return lab, xyz, white
