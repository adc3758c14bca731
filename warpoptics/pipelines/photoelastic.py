"""Strained glass between polarizers: orthoscopic photoelastic images of a stated stress field.

Each point of a plate under plane stress is the retarder of the stress-optic law
(``optics.photoelastic.photoelastic_jones``: retardation C d (sigma_1 - sigma_2), slow along
sigma_1).  Light along the plate normal passes

- the plane polariscope: polarizer at ``polarizer_deg``, the plate, the analyzer crossed
  (+90 degrees): I = sin^2(2 (theta_1 - p)) sin^2(pi Delta / lambda), dark where a principal
  stress is along the polarizer (isoclinics) and where Delta = k lambda (isochromatics);
- the circular polariscope (dark field): polarizer, quarter-wave plate with its slow axis at
  p + 45, the plate, quarter-wave plate at p - 45, analyzer at p + 90 (Frocht 1941,
  Photoelasticity vol. 1): I = sin^2(pi Delta / lambda), isochromatics only.  The quarter-wave
  plates are ideal (achromatic: lambda / 4 at every wavelength, ``optics.plate.wave_plate_jones``).

Monochromatic (intensity) or white light (CIE XYZ under an illuminant, the light behind the
polarizer normalised so that parallel polarizers without a plate give Y = 1; colours as in
``pipelines/microscope.py``).  :func:`brazilian_disc_image` puts the disc under diametral
compression of ``materials.stress`` (strain-free: ``load_n = 0``) on a square image;
:func:`quenched_plate_image` a tempered (or, ``surface_mpa = 0``, annealed) glass plate seen
edge-on, the light crossing ``path_mm`` of glass parallel to its faces.

Image frame: x = image right, y = image up, the loads along y (top and bottom of the disc).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import spectra
from ..color import encode_srgb, gamut_clip
from ..errors import InputError
from ..materials.stress import STRESS_OPTIC_TPA, brazilian_disc, quenched_plate
from ..optics.photoelastic import photoelastic_plates
from ..optics.plate import wave_plates

__all__ = [
    "POLARISCOPES",
    "PhotoelasticImage",
    "polariscope_transmission",
    "photoelastic_image",
    "brazilian_disc_image",
]

POLARISCOPES = ("plane", "circular")


@dataclass(frozen=True)
class PhotoelasticImage:
    """``intensity`` (H, W) at ``wavelength_nm`` or None; ``xyz`` (H, W, 3) in white light or
    None; ``srgb`` (H, W, 3) for display; ``mask`` (H, W) the points inside the part."""

    intensity: np.ndarray | None
    xyz: np.ndarray | None
    srgb: np.ndarray
    mask: np.ndarray
    polariscope: str
    wavelength_nm: float | None


def _c_of(glass, c_tpa):
    if c_tpa is not None:
        if not (isinstance(c_tpa, (int, float)) and np.isfinite(c_tpa)):
            raise InputError("must be a finite number", field="c_tpa", value=c_tpa)
        return float(c_tpa)
    if glass not in STRESS_OPTIC_TPA:
        raise InputError(
            "no stress-optic coefficient", field="glass", value=glass, allowed=", ".join(STRESS_OPTIC_TPA)
        )
    return STRESS_OPTIC_TPA[glass]


def polariscope_transmission(
    sxx_mpa,
    syy_mpa,
    txy_mpa,
    wavelength_nm,
    *,
    c_tpa: float,
    thickness_mm: float,
    polariscope: str = "plane",
    polarizer_deg: float = 0.0,
    device=None,
) -> np.ndarray:
    """Transmitted intensity (..., W) of points with stresses (...) (MPa) between crossed
    polarizers (plane) or crossed circular polarizers, per wavelength (W,) nm."""
    if polariscope not in POLARISCOPES:
        raise InputError(
            "unknown polariscope", field="polariscope", value=polariscope, allowed=", ".join(POLARISCOPES)
        )
    if not (isinstance(thickness_mm, (int, float)) and np.isfinite(thickness_mm) and thickness_mm >= 0):
        raise InputError("must be a number >= 0", field="thickness_mm", value=thickness_mm, allowed=">= 0")
    if not np.isfinite(polarizer_deg):
        raise InputError("must be finite", field="polarizer_deg", value=polarizer_deg)
    lam = np.atleast_1d(np.asarray(wavelength_nm, dtype=np.float64))
    s = [np.asarray(v, dtype=np.float64)[..., None] for v in (sxx_mpa, syy_mpa, txy_mpa)]
    jm = photoelastic_plates(*s, float(c_tpa), float(thickness_mm), lam, device=device)
    if polariscope == "circular":
        q1 = wave_plates(polarizer_deg + 45.0, lam / 4.0, lam, device=device)
        q2 = wave_plates(polarizer_deg - 45.0, lam / 4.0, lam, device=device)
        jm = q2 @ jm @ q1
    p = np.radians(polarizer_deg)
    pol = np.array([np.cos(p), np.sin(p)])
    ana = np.array([-np.sin(p), np.cos(p)])
    return np.abs(np.einsum("i,...ij,j->...", ana, jm, pol)) ** 2


def photoelastic_image(
    sxx_mpa,
    syy_mpa,
    txy_mpa,
    *,
    c_tpa: float,
    thickness_mm: float,
    polariscope: str = "plane",
    polarizer_deg: float = 0.0,
    wavelength_nm: float | None = 589.3,
    illuminant: str = "D65",
    step_nm: float = 10.0,
    exposure: float = 1.0,
    device=None,
) -> PhotoelasticImage:
    """The image of a stress field given on an (H, W) grid (NaN: outside the part, black)."""
    sxx = np.asarray(sxx_mpa, dtype=np.float64)
    if sxx.ndim != 2:
        raise InputError("stress images must be 2-D (H, W)", field="sxx_mpa", value=sxx.shape)
    mask = np.isfinite(sxx) & np.isfinite(syy_mpa) & np.isfinite(txy_mpa)
    pts = [np.asarray(v, dtype=np.float64)[mask] for v in (sxx, syy_mpa, txy_mpa)]
    if wavelength_nm is None:
        if illuminant not in spectra.ILLUMINANTS:
            raise InputError(
                "unknown illuminant",
                field="illuminant",
                value=illuminant,
                allowed=", ".join(spectra.ILLUMINANTS),
            )
        if not step_nm > 0:
            raise InputError("must be > 0", field="step_nm", value=step_nm, allowed="> 0")
        lam = spectra.grid(step=float(step_nm))
    else:
        lam = np.array([float(wavelength_nm)])
    t = polariscope_transmission(
        *pts,
        lam,
        c_tpa=c_tpa,
        thickness_mm=thickness_mm,
        polariscope=polariscope,
        polarizer_deg=polarizer_deg,
        device=device,
    )
    if wavelength_nm is not None:
        img = np.zeros(mask.shape)
        img[mask] = t[:, 0]
        grey = encode_srgb(np.clip(img * exposure, 0.0, 1.0))
        return PhotoelasticImage(
            img, None, np.repeat(grey[..., None], 3, axis=-1), mask, polariscope, float(wavelength_nm)
        )
    xyz = np.zeros((*mask.shape, 3))
    xyz[mask] = spectra.spectrum_to_xyz(lam, t * spectra.illuminant(illuminant, lam))
    rgb = gamut_clip(xyz.reshape(-1, 3) * exposure, 1.0)
    srgb = np.asarray(encode_srgb(rgb)).reshape(*mask.shape, 3)
    return PhotoelasticImage(None, xyz, srgb, mask, polariscope, None)


def brazilian_disc_image(
    *,
    diameter_mm: float = 20.0,
    thickness_mm: float = 5.0,
    load_n: float = 4000.0,
    glass: str = "bk7",
    c_tpa: float | None = None,
    size: int = 161,
    **image,
) -> PhotoelasticImage:
    """:func:`photoelastic_image` of a disc under diametral compression (``materials.stress``),
    ``size`` x ``size`` pixels over the disc's diameter; ``load_n = 0``: strain-free glass.
    ``glass`` names a stress-optic coefficient of ``materials.stress.STRESS_OPTIC_TPA`` unless
    ``c_tpa`` is given.  Further keywords go to :func:`photoelastic_image`."""
    if not (isinstance(size, int) and 8 <= size <= 4096):
        raise InputError("must be an integer in [8, 4096]", field="size", value=size)
    c = _c_of(glass, c_tpa)
    u = ((np.arange(size) + 0.5) / size * 2.0 - 1.0) * 0.5 * diameter_mm
    xx, yy = np.meshgrid(u, -u)  # row 0 at the top: image up = +y
    sxx, syy, txy = brazilian_disc(xx, yy, diameter_mm=diameter_mm, thickness_mm=thickness_mm, load_n=load_n)
    return photoelastic_image(sxx, syy, txy, c_tpa=c, thickness_mm=thickness_mm, **image)


def quenched_plate_image(
    *,
    thickness_mm: float = 6.0,
    path_mm: float = 20.0,
    surface_mpa: float = 100.0,
    glass: str = "bk7",
    c_tpa: float | None = None,
    width: int = 160,
    height: int = 48,
    polarizer_deg: float = 45.0,
    **image,
) -> PhotoelasticImage:
    """A glass plate of ``thickness_mm`` seen edge-on through ``path_mm`` of glass (the light
    parallel to its faces): image x along the plate, y across its thickness (``height`` pixels
    over it).  The residual stress of ``materials.stress.quenched_plate`` acts along x (and
    along the light, which does not change the retardation); across the thickness it is zero,
    so each row is a retarder C L sigma(z) with its axes along x and y.  The plane polariscope
    therefore needs the polarizer away from those axes (default 45 degrees); ``surface_mpa = 0``
    is an annealed plate (black).  Keywords of :func:`photoelastic_image` pass through."""
    if not (
        isinstance(width, int) and 8 <= width <= 4096 and isinstance(height, int) and 8 <= height <= 4096
    ):
        raise InputError("must be integers in [8, 4096]", field="width, height", value=(width, height))
    if not (isinstance(path_mm, (int, float)) and np.isfinite(path_mm) and path_mm > 0):
        raise InputError("must be a number > 0", field="path_mm", value=path_mm, allowed="> 0")
    c = _c_of(glass, c_tpa)
    z = -((np.arange(height) + 0.5) / height - 0.5) * thickness_mm  # row 0 at the top face
    sig = quenched_plate(z, thickness_mm=thickness_mm, surface_mpa=surface_mpa)
    sxx = np.repeat(sig[:, None], width, axis=1)
    zero = np.zeros_like(sxx)
    return photoelastic_image(
        sxx, zero, zero, c_tpa=c, thickness_mm=path_mm, polarizer_deg=polarizer_deg, **image
    )
