"""The polarizing microscope: interference colours of a plate, the Michel-Lévy chart and the
conoscopic (Bertrand-lens) figure, all from the coherent plate of ``stages/polariscope.py``.

- :func:`interference_colour`: a plate of a library (or user) material, thickness and
  orientation, orthoscopic (parallel light along the microscope axis) between the polarizer and
  analyzer -> its spectrum, CIE XYZ under an illuminant, CIELAB, sRGB and its retardation.
- :func:`michel_levy_chart`: the interference colour against retardation 0-2000 nm (crossed
  polarizers, the plate's vibration directions at 45 degrees), computed by the same stage for a
  dispersion-free plate in an index-matched mount, so that the colour depends on the retardation
  alone, as in Michel-Lévy's chart (thickness and birefringence lines are the chart's geometry,
  Delta = d * (n_slow - n_fast)).
- :func:`conoscopic_figure` / :func:`conoscope_profile`: strongly convergent light (numerical
  aperture NA of the condenser and objective), each direction of the cone a plane wave through
  the plate; the objective's back focal plane shows direction (theta, psi) at radius
  NA_pupil = n sin(theta) (Abbe's sine condition), so the image's x, y are n k_x, n k_y / NA.

Conventions: the microscope axis is world +z, image right = world x, image up = world y (an
observer looking down the tube); polarizer and analyzer angles in degrees from image right
toward image up (E-W polarizer, N-S analyzer by default).  ``accessory_nm`` inserts an ideal
accessory plate of that retardation (550: first-order red; 147: quarter-wave) with its slow
direction at ``accessory_deg`` (default 45: NE-SW) in front of the analyzer, the optic-sign test.
Colours: the colour range 360-830 nm, CIE 1931 2 degree observer, illuminants scaled to Y = 1
(``spectra.py``); the light falling on the plate is the illuminant behind the polarizer,
normalised so that parallel polarizers without a plate give Y = 1.  Optical activity is not
modelled unless asked for: ``optical_activity="right"`` (or ``"left"``, or an
``materials.activity.OpticalActivity``) gives a quartz plate its rotatory power
(``optics.plate.plate_active_jones``): the "bull's eye" of a plate cut across the axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import spectra
from ..color import encode_srgb, gamut_clip, xyz_to_lab
from ..errors import InputError
from ..materials.activity import OpticalActivity
from ..materials.activity import optical_activity as _activity_of
from ..materials.dispersion import Biaxial, Isotropic, Material, Uniaxial
from ..optics.biaxial import biaxial_waves
from ..optics.birefringence import extraordinary_index
from ..stages.polariscope import PolariscopeConfig, plate_between_polarizers

__all__ = [
    "InterferenceColour",
    "MichelLevyChart",
    "ConoscopicFigure",
    "plate_optics",
    "plate_retardation",
    "interference_colour",
    "michel_levy_chart",
    "conoscope_profile",
    "conoscopic_figure",
    "resolve_activity",
    "MicroscopeView",
    "stage_turn",
    "random_crystal_axes",
    "voronoi_grains",
    "microscope_view",
    "check_microscope_memory",
    "MICROSCOPE_BYTES_PER_PIXEL",
]

#: the plate of the Michel-Lévy chart: n_o of quartz, birefringence 0.01, mounted in n_o
CHART_N_O = 1.544
CHART_BIREFRINGENCE = 0.01
#: the largest retardation (nm) a Michel-Lévy chart spans (about 180 orders; the colours are a
#: uniform high-order white long before)
MAX_CHART_RETARDATION_NM = 1.0e5


@dataclass(frozen=True)
class InterferenceColour:
    """One plate seen between the polarizers: ``wavelength_nm`` (W,), ``transmission`` (W,)
    (coherent; ``incoherent`` the o and e powers added instead), ``xyz`` (3,), ``lab`` (3,) (D65
    white), ``srgb`` (3,) encoded sRGB in [0, 1] (Smits-Meyer gamut clip at ``exposure``),
    ``retardation_nm`` d |n_1 - n_2| of the two waves along the axis at ``reference_nm``.
    ``band_transmission`` (W,) is ``transmission`` averaged over each sample's band
    (``_band_average``): what the colour integrates, so that a thick plate's fringes, finer
    than the grid, do not alias (the grid itself is refined with the retardation,
    ``_band_grid``)."""

    wavelength_nm: np.ndarray
    transmission: np.ndarray
    incoherent: np.ndarray
    band_transmission: np.ndarray
    xyz: np.ndarray
    lab: np.ndarray
    srgb: np.ndarray
    retardation_nm: float
    reference_nm: float
    exposure: float


@dataclass(frozen=True)
class MichelLevyChart:
    """Interference colours against retardation: ``retardation_nm`` (C,), ``xyz`` (C, 3) (before
    exposure), ``rgb`` (C, 3) linear sRGB after the exposure and the Smits-Meyer clip, ``srgb``
    (C, 3) encoded; the plate model (``n_o``, ``birefringence``, mounting index ``n_o``)."""

    retardation_nm: np.ndarray
    xyz: np.ndarray
    rgb: np.ndarray
    srgb: np.ndarray
    exposure: float
    illuminant: str
    n_o: float
    birefringence: float


@dataclass(frozen=True)
class ConoscopicFigure:
    """The back-focal-plane image: ``intensity`` (H, W) at ``wavelength_nm`` (monochromatic) or
    None; ``xyz`` (H, W, 3) (white light) or None; ``srgb`` (H, W, 3) for display; ``pupil``
    (H, W) bool, the pixels inside the aperture; ``numerical_aperture``."""

    intensity: np.ndarray | None
    xyz: np.ndarray | None
    srgb: np.ndarray
    pupil: np.ndarray
    numerical_aperture: float
    wavelength_nm: float | None


# ---------------------------------------------------------------------------------------------
# materials -> plate arrays


def plate_optics(material: Material, wavelength_nm, *, crystal_axes=None, optic_axis=None):
    """(indices (W, 3), alpha (W, 3), frame (3, 3)) of a plate of ``material`` for the stage:
    (n_o, 0, n_e) / (n_alpha, n_beta, n_gamma) / (n, 0, n).  Wavelengths outside the material's
    data range take its value at the nearest end.  ``optic_axis`` (world) orients a uniaxial
    plate (default: in the plate at 45 degrees, (1, 1, 0)); ``crystal_axes`` (rows X, Y, Z,
    world) a biaxial one (default the material's own turned by 45 degrees about z, so that a
    section normal to Z is in its 45-degree position)."""
    lo, hi = material.wavelength_range_nm
    lam = np.clip(np.atleast_1d(np.asarray(wavelength_nm, dtype=np.float64)), lo, hi)
    if isinstance(material, Biaxial):
        n3 = material.n(lam)
        a3 = material.alpha(lam)
        if crystal_axes is None:
            # the material's own axes turned 45 degrees about the microscope axis: a section
            # normal to Z in its 45-degree position (brightest), not in extinction
            c = np.sqrt(0.5)
            frame = np.asarray(material.crystal_axes, dtype=np.float64) @ np.array(
                [[c, c, 0.0], [-c, c, 0.0], [0.0, 0.0, 1.0]]
            )
        else:
            frame = np.asarray(crystal_axes, dtype=np.float64)
        if frame.shape != (3, 3):
            raise InputError("crystal axes must be a 3x3 matrix (rows X, Y, Z)", field="crystal_axes")
        return n3, a3, frame
    if isinstance(material, Uniaxial):
        n = material.n(lam)
        a = material.alpha(lam)
        zero = np.zeros_like(lam)
        axis = np.asarray((1.0, 1.0, 0.0) if optic_axis is None else optic_axis, dtype=np.float64)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) == 0:
            raise InputError("optic axis must be a non-zero 3-vector", field="optic_axis", value=optic_axis)
        z = axis / np.linalg.norm(axis)
        x = np.cross(z, [1.0, 0.0, 0.0] if abs(z[0]) < 0.9 else [0.0, 1.0, 0.0])
        x /= np.linalg.norm(x)
        frame = np.stack([x, np.cross(z, x), z])
        return (
            np.stack([n[:, 0], zero, n[:, 1]], axis=-1),
            np.stack([a[:, 0], zero, a[:, 1]], axis=-1),
            frame,
        )
    if isinstance(material, Isotropic):
        n = material.n(lam)
        a = material.alpha(lam)
        zero = np.zeros_like(lam)
        return np.stack([n, zero, n], axis=-1), np.stack([a, zero, a], axis=-1), np.eye(3)
    raise InputError("not a material", field="material", value=type(material).__name__)


def plate_retardation(material: Material, thickness_mm: float, *, wavelength_nm: float = 550.0, **orient):
    """Retardation d |n_1 - n_2| (nm) of the two waves of a plate along the microscope axis."""
    return float(_retardation_spectrum(material, thickness_mm, [wavelength_nm], **orient)[0])


def _retardation_spectrum(material: Material, thickness_mm: float, wavelength_nm, **orient) -> np.ndarray:
    """:func:`plate_retardation` (nm) at each of ``wavelength_nm`` (W,)."""
    lam = np.atleast_1d(np.asarray(wavelength_nm, dtype=np.float64))
    frame = plate_optics(material, lam[:1], **orient)[2]
    return _retardation_frames(material, thickness_mm, lam, frame[None])[0]


def _retardation_frames(material: Material, thickness_mm: float, lam: np.ndarray, frames) -> np.ndarray:
    """Retardation (nm) along the microscope axis of plates of ``material`` with the crystal
    ``frames`` (G, 3, 3) (rows X, Y, Z, world), at wavelengths ``lam`` (W,): (G, W)."""
    frames = np.asarray(frames, dtype=np.float64).reshape(-1, 3, 3)
    g, w = frames.shape[0], lam.size
    n3 = plate_optics(material, lam, crystal_axes=np.eye(3), optic_axis=(0.0, 0.0, 1.0))[0]
    if isinstance(material, Biaxial):
        _, _, idx = biaxial_waves(
            np.tile([0.0, 0.0, 1.0], (g * w, 1)),
            np.tile([0.0, 0.0, -1.0], (g * w, 1)),
            np.repeat(frames, w, axis=0),
            np.ones(g * w),
            np.tile(n3[:, 0], g),
            np.tile(n3[:, 1], g),
            np.tile(n3[:, 2], g),
        )
        idx = np.asarray(idx, dtype=np.float64).reshape(g, w, 2)
        dn = np.abs(idx[..., 1] - idx[..., 0])
    elif isinstance(material, Uniaxial):
        cos_t = np.repeat(frames[:, 2, 2], w)
        ne_t = np.asarray(extraordinary_index(cos_t, np.tile(n3[:, 0], g), np.tile(n3[:, 2], g)))
        dn = np.abs(ne_t.astype(np.float64).reshape(g, w) - n3[None, :, 0])
    else:
        dn = np.zeros((g, w))
    return float(thickness_mm) * 1e6 * dn


def _retardation_directions(material: Material, thickness_mm: float, k, lam, frame, n_ambient: float):
    """Retardation (nm) of a plate's two waves for plane waves of unit directions ``k`` (N, 3) in
    the ambient medium (the conoscope's cone), at wavelengths ``lam`` (W,): (N, W).  Both waves
    keep the incident wave's transverse vector s = n_ambient k_xy (Snell), so their phase
    difference is 2 pi d (q_1 - q_2) / lambda with q the normal component of each wave's
    refractive-index vector: sqrt(n_o^2 - s^2) for the ordinary wave, the forward root of the
    extraordinary wave's index surface |N x c|^2 / n_e^2 + (N . c)^2 / n_o^2 = 1 (c the optic
    axis, N = (s, q)), or the two waves of ``optics.biaxial.biaxial_waves``."""
    k = np.asarray(k, dtype=np.float64).reshape(-1, 3)
    lam = np.atleast_1d(np.asarray(lam, dtype=np.float64))
    n3 = plate_optics(material, lam, crystal_axes=np.eye(3), optic_axis=(0.0, 0.0, 1.0))[0]
    nd, w = k.shape[0], lam.size
    if isinstance(material, Biaxial):
        wn, _, idx = biaxial_waves(
            np.repeat(k, w, axis=0),
            np.tile([0.0, 0.0, -1.0], (nd * w, 1)),
            np.broadcast_to(np.asarray(frame, dtype=np.float64), (nd * w, 3, 3)),
            np.full(nd * w, float(n_ambient)),
            np.tile(n3[:, 0], nd),
            np.tile(n3[:, 1], nd),
            np.tile(n3[:, 2], nd),
        )
        q = (
            np.asarray(idx, dtype=np.float64).reshape(nd, w, 2)
            * np.asarray(wn, dtype=np.float64).reshape(nd, w, 2, 3)[..., 2]
        )
        dq = np.abs(q[..., 1] - q[..., 0])
    elif isinstance(material, Uniaxial):
        c = np.asarray(frame, dtype=np.float64)[2]
        c = c / np.linalg.norm(c)
        sxy = float(n_ambient) * k[:, :2]  # (N, 2)
        s2 = np.sum(sxy**2, axis=1)[:, None]
        a = (sxy @ c[:2])[:, None]
        no2, ne2 = n3[None, :, 0] ** 2, n3[None, :, 2] ** 2
        qa = (1.0 - c[2] ** 2) / ne2 + c[2] ** 2 / no2
        qb = 2.0 * a * c[2] * (1.0 / no2 - 1.0 / ne2)
        qc = (s2 - a**2) / ne2 + a**2 / no2 - 1.0
        q_e = (-qb + np.sqrt(np.maximum(qb**2 - 4.0 * qa * qc, 0.0))) / (2.0 * qa)
        q_o = np.sqrt(np.maximum(no2 - s2, 0.0))
        dq = np.abs(q_e - q_o)
    else:
        dq = np.zeros((nd, w))
    return float(thickness_mm) * 1e6 * dq


#: the finest wavelength grid a colour integral refines to (``_band_grid``): 470 nm in 20000 steps
MAX_COLOUR_SAMPLES = 20001


def _band_grid(step_nm: float, retardation_nm) -> np.ndarray:
    """The wavelength grid of a colour integral of a plate whose retardation is at most
    ``retardation_nm``: ``step_nm``, refined until the fastest fringe (period lambda^2 / Delta,
    shortest at 360 nm) has at least four samples, and no finer than
    :data:`MAX_COLOUR_SAMPLES` over 360-830 nm (beyond that the fringes are averaged away by
    :func:`_band_average`, which holds for any grid)."""
    lam = _colour_grid(step_nm)
    r = float(np.max(retardation_nm, initial=0.0))
    if r > 0.0:
        period = spectra.LAMBDA_MIN**2 / r
        floor = (spectra.LAMBDA_MAX - spectra.LAMBDA_MIN) / (MAX_COLOUR_SAMPLES - 1)
        h = max(min(float(step_nm), period / 4.0), floor)
        if h < float(step_nm):
            lam = spectra.grid(step=h)
    return lam


def _band_average(coherent, incoherent, wavelength_nm, retardation_nm) -> np.ndarray:
    """The coherent transmission averaged over each sample's band of the wavelength grid.

    Two waves through the plate add as I = I_o + I_e + 2 Re(a_o a_e* exp(i delta)) with
    delta = 2 pi Delta / lambda: the incoherent part I_o + I_e (the stage's ``incoherent``) and
    a fringe term (``coherent - incoherent``).  Over a band of width h the phase runs linearly
    at delta' = d delta / d lambda, so the band mean of the fringe term is its value times
    sin(x) / x, x = delta' h / 2 (the mean of cos(delta_0 + delta' u) for |u| <= h / 2).  A
    thick plate, whose fringes are far finer than the band, keeps the incoherent part alone:
    neutral (Michel-Levy's "high-order white"), where point samples alias into false colours.
    ``retardation_nm`` (..., W) broadcasts against ``coherent`` (..., W)."""
    lam = np.asarray(wavelength_nm, dtype=np.float64)
    coh = np.asarray(coherent, dtype=np.float64)
    inc = np.asarray(incoherent, dtype=np.float64)
    if lam.size < 2:
        return coh
    delta = 2.0 * np.pi * np.asarray(retardation_nm, dtype=np.float64) / lam
    slope = np.gradient(delta, lam, axis=-1)
    h = np.gradient(lam)  # the band of each sample (trapezoid weights / 1)
    return inc + (coh - inc) * np.sinc(slope * h / (2.0 * np.pi))


# ---------------------------------------------------------------------------------------------
# colours


def _colour_grid(step_nm: float) -> np.ndarray:
    if not step_nm > 0:
        raise InputError("wavelength step must be > 0", field="step_nm", value=step_nm, allowed="> 0")
    return spectra.grid(step=float(step_nm))


def _xyz(lam: np.ndarray, transmission: np.ndarray, illuminant: str) -> np.ndarray:
    if illuminant not in spectra.ILLUMINANTS:
        raise InputError(
            "unknown illuminant", field="illuminant", value=illuminant, allowed=", ".join(spectra.ILLUMINANTS)
        )
    return spectra.spectrum_to_xyz(lam, transmission * spectra.illuminant(illuminant, lam))


def _display(xyz: np.ndarray, exposure: float) -> tuple[np.ndarray, np.ndarray]:
    rgb = gamut_clip(np.asarray(xyz, dtype=np.float64) * exposure, 1.0)
    return rgb, np.asarray(encode_srgb(rgb))


def _orientation(material, optic_axis, crystal_axes) -> dict:
    """The orientation keyword of a plate: its optic axis, or a biaxial crystal's axes."""
    return {"crystal_axes": crystal_axes} if isinstance(material, Biaxial) else {"optic_axis": optic_axis}


def _through_plate(
    material,
    k,
    thickness_mm,
    wavelength_nm,
    optic_axis,
    crystal_axes,
    polarizer_deg,
    analyzer_deg,
    accessory_nm,
    accessory_deg,
    n_ambient,
    device,
    optical_activity=None,
):
    """(coherent, incoherent) intensities of a plate of ``material`` (oriented by ``optic_axis``,
    or ``crystal_axes`` for a biaxial one) between the polarizers, per direction x wavelength;
    ``optical_activity`` (:func:`resolve_activity`) couples the waves of the coherent result."""
    n3, a3, frame = plate_optics(material, wavelength_nm, **_orientation(material, optic_axis, crystal_axes))
    cfg = PolariscopeConfig(
        polarizer_deg=polarizer_deg,
        analyzer_deg=analyzer_deg,
        n_ambient=n_ambient,
        accessory_nm=accessory_nm,
        accessory_deg=accessory_deg,
    )
    act = resolve_activity(material, optical_activity)
    if act is None:
        return plate_between_polarizers(
            k, thickness_mm, wavelength_nm, n3, crystal_frame=frame, alpha=a3, config=cfg, device=device
        )
    return plate_between_polarizers(
        k,
        thickness_mm,
        wavelength_nm,
        n3,
        crystal_frame=frame,
        alpha=a3,
        config=cfg,
        rotatory_rad_mm=act.rho_rad_mm(wavelength_nm),
        rotatory_ratio=act.perpendicular_ratio,
        device=device,
    )


def interference_colour(
    material: Material,
    thickness_mm: float,
    *,
    optic_axis=None,
    crystal_axes=None,
    polarizer_deg: float = 0.0,
    analyzer_deg: float = 90.0,
    accessory_nm: float = 0.0,
    accessory_deg: float = 45.0,
    n_ambient: float = 1.0,
    illuminant: str = "D65",
    step_nm: float = 5.0,
    exposure: float = 1.0,
    reference_nm: float = 550.0,
    optical_activity=None,
    device=None,
) -> InterferenceColour:
    """The interference colour of a plate (orthoscopic, light along the microscope axis)."""
    if not (isinstance(thickness_mm, (int, float)) and np.isfinite(thickness_mm) and thickness_mm >= 0):
        raise InputError("must be a number >= 0", field="thickness_mm", value=thickness_mm, allowed=">= 0")
    orient = _orientation(material, optic_axis, crystal_axes)
    frame = plate_optics(material, 550.0, **orient)[2]
    lam, coh, inc, band = _plates_between_polarizers(
        material,
        thickness_mm,
        frame[None],
        step_nm=step_nm,
        polarizer_deg=polarizer_deg,
        analyzer_deg=analyzer_deg,
        accessory_nm=accessory_nm,
        accessory_deg=accessory_deg,
        n_ambient=n_ambient,
        optical_activity=optical_activity,
        device=device,
    )
    coh, inc, band = coh[0], inc[0], band[0]
    xyz = _xyz(lam, band, illuminant)
    _, srgb = _display(xyz, exposure)
    return InterferenceColour(
        wavelength_nm=lam,
        transmission=coh,
        incoherent=inc,
        band_transmission=band,
        xyz=xyz,
        lab=xyz_to_lab(xyz),
        srgb=srgb,
        retardation_nm=plate_retardation(material, thickness_mm, wavelength_nm=reference_nm, **orient),
        reference_nm=float(reference_nm),
        exposure=float(exposure),
    )


def _plates_between_polarizers(
    material: Material,
    thickness_mm: float,
    frames,
    *,
    step_nm: float,
    polarizer_deg: float,
    analyzer_deg: float,
    accessory_nm: float,
    accessory_deg: float,
    n_ambient: float,
    optical_activity,
    device,
):
    """Plates of ``material`` in the crystal ``frames`` (G, 3, 3) (rows X, Y, Z, world; a
    uniaxial plate's optic axis is row Z) seen orthoscopically between the polarizers, all in
    one launch: (wavelengths (W,), coherent (G, W), incoherent (G, W), band-averaged coherent
    (G, W)) on the grid :func:`_band_grid` refines for the largest retardation."""
    frames = np.asarray(frames, dtype=np.float64).reshape(-1, 3, 3)
    g = frames.shape[0]
    act = resolve_activity(material, optical_activity)
    ret_max = _retardation_frames(material, thickness_mm, _colour_grid(step_nm), frames)
    lam = _band_grid(step_nm, ret_max)
    n3, a3, _ = plate_optics(material, lam, crystal_axes=np.eye(3), optic_axis=(0.0, 0.0, 1.0))
    cfg = PolariscopeConfig(
        polarizer_deg=polarizer_deg,
        analyzer_deg=analyzer_deg,
        n_ambient=n_ambient,
        accessory_nm=accessory_nm,
        accessory_deg=accessory_deg,
    )
    kw: dict = {"crystal_frame": frames, "alpha": a3, "config": cfg, "device": device}
    if act is not None:
        kw.update(rotatory_rad_mm=act.rho_rad_mm(lam), rotatory_ratio=act.perpendicular_ratio)
    coh, inc = plate_between_polarizers(np.tile([0.0, 0.0, 1.0], (g, 1)), thickness_mm, lam, n3, **kw)
    if act is None:
        band = _band_average(coh, inc, lam, _retardation_frames(material, thickness_mm, lam, frames))
    else:  # optically active: the waves are coupled, not two fringes of one phase (point samples)
        band = coh
    return lam, coh, inc, band


def michel_levy_chart(
    *,
    max_retardation_nm: float = 2000.0,
    columns: int = 801,
    illuminant: str = "D65",
    step_nm: float = 5.0,
    exposure: float | None = None,
    device=None,
) -> MichelLevyChart:
    """The Michel-Lévy colours for retardations 0..``max_retardation_nm`` (``columns`` samples):
    a plate of n_o = 1.544, n_e = n_o + 0.01 (no dispersion), mounted in a medium of index n_o,
    its vibration directions at 45 degrees to crossed polarizers, thickness Delta / 0.01.
    ``exposure`` scales XYZ before the gamut clip (default: the brightest colour gets Y = 1)."""
    if not (isinstance(columns, int) and columns >= 2):
        raise InputError("must be an integer >= 2", field="columns", value=columns)
    if not (np.isfinite(max_retardation_nm) and 0 < max_retardation_nm <= MAX_CHART_RETARDATION_NM):
        raise InputError(
            "out of range (past ~5000 nm every colour is the same high-order white)",
            field="max_retardation_nm",
            value=max_retardation_nm,
            allowed=f"> 0 and <= {MAX_CHART_RETARDATION_NM:g} nm",
        )
    lam = _band_grid(step_nm, max_retardation_nm)
    ret = np.linspace(0.0, float(max_retardation_nm), columns)
    n3 = np.tile([CHART_N_O, 0.0, CHART_N_O + CHART_BIREFRINGENCE], (lam.size, 1))
    s = np.sqrt(0.5)
    frame = np.array([[0.0, 0.0, 1.0], [-s, s, 0.0], [s, s, 0.0]])  # optic axis at 45 degrees
    k = np.tile([0.0, 0.0, 1.0], (columns, 1))
    cfg = PolariscopeConfig(n_ambient=CHART_N_O)
    coh, inc = plate_between_polarizers(
        k, ret * 1e-6 / CHART_BIREFRINGENCE, lam, n3, crystal_frame=frame, config=cfg, device=device
    )
    xyz = _xyz(lam, _band_average(coh, inc, lam, np.broadcast_to(ret[:, None], coh.shape)), illuminant)
    if exposure is None:
        exposure = 1.0 / float(np.max(xyz[:, 1]))
    rgb, srgb = _display(xyz, exposure)
    return MichelLevyChart(
        retardation_nm=ret,
        xyz=xyz,
        rgb=rgb,
        srgb=srgb,
        exposure=float(exposure),
        illuminant=illuminant,
        n_o=CHART_N_O,
        birefringence=CHART_BIREFRINGENCE,
    )


# ---------------------------------------------------------------------------------------------
# conoscope


def _cone_directions(pupil_xy: np.ndarray, numerical_aperture: float, n_ambient: float) -> np.ndarray:
    """Unit directions of pupil points (x, y) in [-1, 1] (radius 1 = the aperture)."""
    st = np.asarray(pupil_xy, dtype=np.float64) * (numerical_aperture / n_ambient)
    kz = np.sqrt(np.maximum(1.0 - np.sum(st**2, axis=-1), 0.0))
    return np.concatenate([st, kz[..., None]], axis=-1)


def _check_na(numerical_aperture: float, n_ambient: float) -> None:
    if not (np.isfinite(numerical_aperture) and 0 < numerical_aperture < n_ambient):
        raise InputError(
            "numerical aperture must be in (0, n_ambient)",
            field="numerical_aperture",
            value=numerical_aperture,
            allowed=f"(0, {n_ambient:g})",
        )


def conoscope_profile(
    material: Material,
    thickness_mm: float,
    radius,
    *,
    azimuth_deg: float = 45.0,
    wavelength_nm: float = 589.3,
    numerical_aperture: float = 0.5,
    optic_axis=(0.0, 0.0, 1.0),
    crystal_axes=None,
    polarizer_deg: float = 0.0,
    analyzer_deg: float = 90.0,
    accessory_nm: float = 0.0,
    accessory_deg: float = 45.0,
    n_ambient: float = 1.0,
    optical_activity=None,
    device=None,
) -> np.ndarray:
    """Transmitted intensity along a radius of the conoscopic figure: ``radius`` (R,) in units
    of the aperture (0 centre, 1 edge: n sin(theta) = NA * radius) at ``azimuth_deg``."""
    _check_na(numerical_aperture, n_ambient)
    r = np.asarray(radius, dtype=np.float64)
    psi = np.radians(azimuth_deg)
    xy = np.stack([r * np.cos(psi), r * np.sin(psi)], axis=-1)
    k = _cone_directions(xy, numerical_aperture, n_ambient)
    coh, _ = _through_plate(
        material,
        k,
        thickness_mm,
        [wavelength_nm],
        optic_axis,
        crystal_axes,
        polarizer_deg,
        analyzer_deg,
        accessory_nm,
        accessory_deg,
        n_ambient,
        device,
        optical_activity,
    )
    return coh[:, 0]


def conoscopic_figure(
    material: Material,
    thickness_mm: float,
    *,
    size: int = 201,
    numerical_aperture: float = 0.5,
    wavelength_nm: float | None = 589.3,
    optic_axis=(0.0, 0.0, 1.0),
    crystal_axes=None,
    polarizer_deg: float = 0.0,
    analyzer_deg: float = 90.0,
    accessory_nm: float = 0.0,
    accessory_deg: float = 45.0,
    n_ambient: float = 1.0,
    illuminant: str = "D65",
    step_nm: float = 10.0,
    exposure: float | None = None,
    optical_activity=None,
    device=None,
) -> ConoscopicFigure:
    """The conoscopic figure of a plate (default: cut across its optic axis) in the objective's
    back focal plane, ``size`` x ``size`` pixels over the aperture; monochromatic at
    ``wavelength_nm`` or, with ``wavelength_nm=None``, in white light (``illuminant``)."""
    _check_na(numerical_aperture, n_ambient)
    if not (isinstance(size, int) and 8 <= size <= 4096):
        raise InputError("must be an integer in [8, 4096]", field="size", value=size)
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    xx, yy = np.meshgrid(c, -c)  # row 0 at the top: image up = world +y
    pupil = xx**2 + yy**2 <= 1.0
    k = _cone_directions(np.stack([xx[pupil], yy[pupil]], axis=-1), numerical_aperture, n_ambient)
    lam = np.array([float(wavelength_nm)]) if wavelength_nm is not None else _colour_grid(step_nm)
    coh, inc = _through_plate(
        material,
        k,
        thickness_mm,
        lam,
        optic_axis,
        crystal_axes,
        polarizer_deg,
        analyzer_deg,
        accessory_nm,
        accessory_deg,
        n_ambient,
        device,
        optical_activity,
    )
    if wavelength_nm is not None:
        img = np.zeros((size, size))
        img[pupil] = coh[:, 0]
        peak = float(img.max()) if exposure is None else 1.0 / float(exposure)
        grey = encode_srgb(np.clip(img / max(peak, 1e-12), 0.0, 1.0))
        return ConoscopicFigure(
            img, None, np.repeat(grey[..., None], 3, axis=-1), pupil, numerical_aperture, float(wavelength_nm)
        )
    if resolve_activity(material, optical_activity) is None:
        # white light: each direction's fringes averaged over the wavelength bands (_band_average),
        # so that the high orders toward the rim are white, not aliased colours
        frame = plate_optics(material, 550.0, **_orientation(material, optic_axis, crystal_axes))[2]
        ret = _retardation_directions(material, thickness_mm, k, lam, frame, n_ambient)
        coh = _band_average(coh, inc, lam, ret)
    xyz = np.zeros((size, size, 3))
    xyz[pupil] = _xyz(lam, coh, illuminant)
    if exposure is None:
        exposure = 1.0 / max(float(np.max(xyz[..., 1])), 1e-12)
    _, srgb = _display(xyz.reshape(-1, 3), exposure)
    return ConoscopicFigure(None, xyz, srgb.reshape(size, size, 3), pupil, numerical_aperture, None)


# ---------------------------------------------------------------------------------------------
# optical activity


def resolve_activity(material: Material, optical_activity) -> OpticalActivity | None:
    """The :class:`OpticalActivity` a plate of ``material`` is given: None (none), an
    ``OpticalActivity``, or a handedness ``"right"`` / ``"left"`` looked up by the material's
    name (``materials.activity.optical_activity``; quartz)."""
    if optical_activity is None:
        return None
    if isinstance(material, Biaxial):
        raise InputError("optical activity is modelled for uniaxial plates only", field="optical_activity")
    if isinstance(optical_activity, OpticalActivity):
        act = optical_activity
    elif isinstance(optical_activity, str):
        act = _activity_of(getattr(material, "name", ""), optical_activity)
    else:
        raise InputError(
            "must be None, 'right', 'left' or an OpticalActivity",
            field="optical_activity",
            value=type(optical_activity).__name__,
        )
    return act


# ---------------------------------------------------------------------------------------------
# microscope scenes (scene/microscope.py): orthoscopic views of plates and thin sections,
# conoscopic figures, from a TOML file


@dataclass(frozen=True)
class MicroscopeView:
    """What :func:`microscope_view` returns: ``xyz`` (H, W, 3) (the illuminant behind the
    polarizer has Y = 1, as in :func:`interference_colour`), ``srgb`` (H, W, 3) encoded;
    thin sections also ``grain`` (H, W) int (the grain each pixel sees), ``orientations``
    (G, 3) (each grain's optic axis, or Z of a biaxial grain, in the section frame, before the
    stage rotation), ``crystal_axes`` (G, 3, 3) (rows X, Y, Z) and ``grain_xyz`` (G, 3)
    (without accessory wedge; None with it); ``title`` a one-line description."""

    xyz: np.ndarray
    srgb: np.ndarray
    grain: np.ndarray | None = None
    orientations: np.ndarray | None = None
    crystal_axes: np.ndarray | None = None
    grain_xyz: np.ndarray | None = None
    title: str = ""


def stage_turn(deg: float) -> np.ndarray:
    """The rotation matrix of the stage turned counter-clockwise by ``deg`` about the
    microscope axis (world z), seen down the tube."""
    t = np.radians(float(deg))
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def random_crystal_axes(count: int, seed: int) -> np.ndarray:
    """(count, 3, 3) orientations drawn uniformly over the rotation group (rows X, Y, Z): Z
    (a uniaxial grain's optic axis) is then uniform on the sphere.  Z from a normalised 3-D
    Gaussian (Muller 1959), X from a second Gaussian made perpendicular to it."""
    rng = np.random.default_rng(int(seed))
    z = rng.standard_normal((count, 3))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    x = rng.standard_normal((count, 3))
    x -= z * np.sum(x * z, axis=1, keepdims=True)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=1)


def voronoi_grains(count: int, seed: int, size: int, field_mm: float, stage_deg: float = 0.0):
    """A thin section's grain map: ``count`` cell centres uniform over the field (drawn after
    the orientations from the same ``seed``), each pixel (size x size over ``field_mm``, row 0
    at the top) given the index of the nearest centre of the section turned by ``stage_deg``.
    Returns (grain (size, size) int, centres (count, 2) mm in the section frame)."""
    rng = np.random.default_rng(int(seed) + 1)
    centres = (rng.random((count, 2)) - 0.5) * field_mm
    c = ((np.arange(size) + 0.5) / size - 0.5) * field_mm
    xx, yy = np.meshgrid(c, -c)
    turn = stage_turn(-stage_deg)[:2, :2]  # the section point under each pixel
    p = np.stack([xx.ravel(), yy.ravel()], axis=-1) @ turn.T
    from scipy.spatial import cKDTree

    grain = np.empty(p.shape[0], dtype=np.int64)
    tree = cKDTree(centres)  # O(P log G): 4096^2 pixels over 4096 grains in seconds
    chunk = 1 << 18
    starts = range(0, p.shape[0], chunk)
    bar = None
    if p.shape[0] > 4 * chunk:  # long work shows its progress (above 1024 x 1024 pixels)
        from tqdm.auto import tqdm

        bar = tqdm(total=p.shape[0], unit="px", unit_scale=True, desc="grains", leave=False)
    for a in starts:
        _, grain[a : a + chunk] = tree.query(p[a : a + chunk], workers=-1)
        if bar is not None:
            bar.update(min(chunk, p.shape[0] - a))
    if bar is not None:
        bar.close()
    return grain.reshape(size, size), centres


def _orient_kw(material, axes: np.ndarray | None) -> dict:
    """The orientation keyword of :func:`interference_colour` for world ``axes`` (rows X, Y, Z)."""
    if axes is None or isinstance(material, Isotropic):
        return {}
    if isinstance(material, Biaxial):
        return {"crystal_axes": axes}
    return {"optic_axis": tuple(axes[2])}


def _sample_axes(sample, default_z: tuple[float, float, float] | None) -> np.ndarray | None:
    """The plate's frame (rows X, Y, Z, world, before the stage) from its scene config: its
    ``crystal_axes``, a frame about its ``optic_axis`` (else ``default_z``), else the defaults
    of :func:`plate_optics`; None for an isotropic plate."""
    mat = sample.material
    if isinstance(mat, Isotropic):
        return None
    if sample.crystal_axes is not None:
        return np.asarray(sample.crystal_axes, dtype=np.float64)
    axis = sample.optic_axis if sample.optic_axis is not None else default_z
    return plate_optics(mat, 550.0, optic_axis=axis)[2]


def _analyzed_colour(sample, thickness_mm, axes, mic, accessory_nm, device) -> np.ndarray:
    """XYZ of one plate (frame ``axes`` in world, or None: the material's default) between the
    scene's polarizer and analyzer (:func:`_analyzed_colours`)."""
    frame = plate_optics(sample.material, 550.0, **_orient_kw(sample.material, axes))[2]
    return _analyzed_colours(sample, thickness_mm, frame[None], mic, accessory_nm, device)[0]


def _analyzed_colours(sample, thickness_mm, frames, mic, accessory_nm, device) -> np.ndarray:
    """XYZ (G, 3) of plates of the sample's material in the crystal ``frames`` (G, 3, 3) (rows
    X, Y, Z, world), all in one launch per analyzer position, between the scene's polarizer and
    analyzer (``mic.analyzer`` None: both analyzer positions summed, i.e. the power behind the
    plate: plane-polarized light); the colours of :func:`interference_colour`."""
    analyzers = [mic.analyzer] if mic.analyzer is not None else [mic.polarizer, mic.polarizer + 90.0]
    out = np.zeros((np.asarray(frames).reshape(-1, 9).shape[0], 3))
    for a in analyzers:
        lam, _, _, band = _plates_between_polarizers(
            sample.material,
            thickness_mm,
            frames,
            step_nm=5.0,
            polarizer_deg=mic.polarizer,
            analyzer_deg=a,
            accessory_nm=accessory_nm,
            accessory_deg=mic.accessory_angle,
            n_ambient=mic.mounting_index,
            optical_activity=sample.optical_activity,
            device=device,
        )
        out += _xyz(lam, band, mic.illuminant)
    return out


def _wedge_columns(size: int, max_nm: float, steps: int = 128) -> tuple[np.ndarray, np.ndarray]:
    """Quartz wedge: the column groups (size,) int and their retardations (steps,) nm, a ramp
    from 0 at the left edge to ``max_nm`` at the right in ``steps`` flat strips."""
    steps = min(steps, size)
    col = np.minimum((np.arange(size) * steps) // size, steps - 1)
    return col, (np.arange(steps) + 0.5) / steps * max_nm


#: peak memory per pixel of a view (measured: 2.9 GB for a 4096 x 4096 thin section of 4096
#: grains, with its PNG written): the grain map, XYZ and sRGB images, the KD-tree queries
MICROSCOPE_BYTES_PER_PIXEL = 180


def check_microscope_memory(size: int, *, available: int | None = None, file=None) -> int:
    """Refuse (InputError with the estimate in GiB) a ``size`` x ``size`` view that would not fit
    in ``available`` bytes (default: what the system has free now).  Returns the estimate."""
    from .render import available_memory_bytes

    need = int(size) * int(size) * MICROSCOPE_BYTES_PER_PIXEL
    avail = available_memory_bytes() if available is None else int(available)
    if avail is not None and need > avail:
        raise InputError(
            f"the view would need about {need / 2**30:.1f} GiB of memory but only {avail / 2**30:.1f} GiB "
            "is available; give a smaller size",
            file=None if file is None else str(file),
            field="microscope.size",
            value=int(size),
        )
    return need


def microscope_view(scene, *, device=None) -> MicroscopeView:
    """The view of a :class:`~warpoptics.scene.microscope.MicroscopeScene`: orthoscopic (each
    pixel the interference colour of the plate or grain under it, parallel light along the
    axis; an accessory plate or the quartz wedge in front of the analyzer) or conoscopic (the
    Bertrand-lens figure of the plate, :func:`conoscopic_figure`).  The stage turns the sample
    (its orientation and the grain map) counter-clockwise by ``stage_rotation``."""
    mic, sample = scene.microscope, scene.sample
    mat, d, size = sample.material, sample.thickness_mm, mic.size
    check_microscope_memory(size, file=getattr(scene, "path", None))
    turn = stage_turn(mic.stage_rotation)
    wedge = mic.accessory == "quartz_wedge"
    ana = "none" if mic.analyzer is None else f"{mic.analyzer:g}"
    where = f"polarizer {mic.polarizer:g}, analyzer {ana}, stage {mic.stage_rotation:g} deg"
    if mic.accessory != "none":
        where += f", {mic.accessory.replace('_', ' ')} ({mic.accessory_nm:g} nm)"
    if mic.mode == "conoscopic":
        axes = _sample_axes(sample, (0.0, 0.0, 1.0) if isinstance(mat, Uniaxial) else None)
        axes_w = None if axes is None else axes @ turn.T
        kw = dict(
            size=size,
            numerical_aperture=mic.numerical_aperture,
            wavelength_nm=mic.wavelength,
            polarizer_deg=mic.polarizer,
            optical_activity=sample.optical_activity,
            accessory_nm=mic.accessory_nm,
            accessory_deg=mic.accessory_angle,
            n_ambient=mic.mounting_index,
            illuminant=mic.illuminant,
            device=device,
            **_orient_kw(mat, axes_w),
        )
        if "optic_axis" not in kw and not isinstance(mat, Biaxial):
            kw["optic_axis"] = (0.0, 0.0, 1.0)
        analyzers = [mic.analyzer] if mic.analyzer is not None else [mic.polarizer, mic.polarizer + 90.0]
        figs = [conoscopic_figure(mat, d, analyzer_deg=a, exposure=1.0, **kw) for a in analyzers]
        light = "white light" if mic.wavelength is None else f"{mic.wavelength:g} nm"
        title = (
            f"{sample.material_name} {d:g} mm, conoscopic, NA {mic.numerical_aperture:g}, {light}; {where}"
        )
        if mic.wavelength is not None:
            y = np.sum([np.asarray(f.intensity) for f in figs], axis=0)
            xyz = np.repeat(y[..., None], 3, axis=-1)  # monochromatic: grey
            srgb = np.repeat(
                np.asarray(encode_srgb(np.clip(y / max(float(y.max()), 1e-12), 0, 1)))[..., None], 3, -1
            )
            return MicroscopeView(xyz=xyz, srgb=srgb, title=title)
        xyz = np.sum([np.asarray(f.xyz) for f in figs], axis=0)
        exposure = 1.0 / max(float(np.max(xyz[..., 1])), 1e-12)
        _, srgb = _display(xyz.reshape(-1, 3), exposure)
        return MicroscopeView(xyz=xyz, srgb=srgb.reshape(size, size, 3), title=title)
    # orthoscopic
    col, ret = _wedge_columns(size, mic.wedge_max_nm)  # used with the quartz wedge only
    if sample.kind == "plate":
        axes = _sample_axes(sample, None)
        axes_w = None if axes is None else axes @ turn.T
        if wedge:
            strips = np.array([_analyzed_colour(sample, d, axes_w, mic, r, device) for r in ret])
            xyz = np.broadcast_to(strips[col][None, :, :], (size, size, 3)).copy()
        else:
            xyz = np.broadcast_to(
                _analyzed_colour(sample, d, axes_w, mic, mic.accessory_nm, device), (size, size, 3)
            )
            xyz = xyz.copy()
        _, srgb = _display(xyz.reshape(-1, 3), 1.0)
        title = f"{sample.material_name} plate {d * 1000:g} um, orthoscopic; {where}"
        return MicroscopeView(xyz=xyz, srgb=srgb.reshape(size, size, 3), title=title)
    axes = random_crystal_axes(sample.grains, sample.seed)
    grain, _ = voronoi_grains(sample.grains, sample.seed, size, mic.field_mm, mic.stage_rotation)
    axes_w = axes @ turn.T  # rows turned: (R a_k)^T = a_k^T R^T
    if wedge:
        xyz = np.zeros((size, size, 3))
        srgb = np.zeros((size, size, 3))
        for s, r in enumerate(ret):  # every grain at each strip's wedge retardation, one launch
            cols = col == s
            strip_xyz = _analyzed_colours(sample, d, axes_w, mic, r, device)
            xyz[:, cols] = strip_xyz[grain[:, cols]]
            srgb[:, cols] = _display(strip_xyz, 1.0)[1][grain[:, cols]]
        grain_xyz = None
    else:
        grain_xyz = _analyzed_colours(sample, d, axes_w, mic, mic.accessory_nm, device)
        xyz = grain_xyz[grain]
        srgb = _display(grain_xyz, 1.0)[1][grain]  # a colour per grain, displayed once per grain
    title = (
        f"{sample.material_name} thin section {d * 1000:g} um, {sample.grains} grains, orthoscopic; {where}"
    )
    return MicroscopeView(
        xyz=xyz,
        srgb=srgb,
        grain=grain,
        orientations=axes[:, 2, :].copy(),
        crystal_axes=axes,
        grain_xyz=grain_xyz,
        title=title,
    )
