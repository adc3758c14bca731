"""Light-performance metrics over a tilt protocol with the observer's head (after GIA and AGS).

**The protocol** (:data:`PROTOCOL`, :func:`tilted_light_return`): the stone is seen by an observer
at 250 mm on its axis (:func:`~warpoptics.grading.presets.face_up_scene`, perspective camera)
under isotropic light (GemRay's ISO: the uniform D65 ``dome`` over the girdle plane) from which
the observer's head blocks a cone of :data:`~warpoptics.grading.presets.HEAD_RADIUS_DEG` (10 deg)
radius about the line of sight.  The stone is rocked: face-up and tilted by 5, 10, 15 and 20 deg
about two horizontal axes, across a pavilion main (azimuth 0) and between two mains (22.5 deg; the
brilliant's 8-fold, mirror-symmetric pattern makes these the two distinct tilt directions).  The
head stays with the observer while the stone tilts.  For each of the 9 distinct views the light
return is the stone's alpha-weighted mean luminance relative to the unobstructed dome
(:func:`warpoptics.metrics.light_return`); the protocol's value is their plain mean.

Where this follows and where it differs from the sources:

- GIA (Hemphill et al. 1998, Moses et al. 2004; GIA Diamond Cut Research Technical FAQ) computes
  brightness as weighted light return under diffuse light with a dark region for the observer
  (23 deg radius in its brightness metric) and accounts for the tilting of stones in observation.
  GIA integrates every ray leaving the crown with a cosine weight; ours averages images of a real
  observer's view at discrete tilts.  GIA's 23 deg dark area is available (``head_radius_deg``,
  the ``grading_dome`` lighting); with it the curve's maximum moves to deeper pavilions (the README
  gives the measured table for 10, 15 and 23 deg).  The 10 deg default is the obstruction of a
  face about 9 cm wide at 25 cm, the observer geometry of the AGS ASET work (Sasian et al. 2007).
- AGS (Sasian et al. 2007) evaluate light return with the observer at 25 cm and the head
  obstruction, over tilts; their weights of the ASET zones are not reproduced here.
- Spectral, polarized transport with the renderer's depth / energy cut-off (``max_depth`` 12).

Further metrics of one view (each a function of a render's ``xyz`` and ``alpha``):

- :func:`contrast` — C = sqrt(Σ α (Y − Ȳ)² / Σ α) / Ȳ, the coefficient of variation of the stone's
  luminance (unitless; 0 for a uniformly bright stone); the face-up pattern's light/dark contrast
  after DiamCalc's and Sasian et al.'s use of the term.
- :func:`extinction` — the alpha-weighted fraction of the stone's area darker than
  ``threshold`` (default 0.15) of the dome's white (unitless, [0, 1]): the dark areas that appear
  under tilt and head obstruction (faceters' "extinction").
- :func:`windowing` — from a :class:`~warpoptics.grading.scopes.Bands` decomposition: the
  alpha-weighted fraction of the stone's area where more than half of the pixel's light comes
  from below the girdle plane (see-through "window", unitless).
- :func:`bow_tie` — for elongated fancy shapes: the mean luminance of a band across the centre
  along the short axis (width ``band`` of the width) relative to the whole stone's, subtracted from
  1: > 0 when a dark bow-tie crosses the centre (unitless).

References: see :mod:`warpoptics.grading.presets` and :mod:`warpoptics.grading.scopes`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import metrics as wm
from ..errors import InputError
from .presets import HEAD_RADIUS_DEG, face_up_scene

__all__ = [
    "Protocol",
    "PROTOCOL",
    "tilted_views",
    "tilted_light_return",
    "contrast",
    "extinction",
    "windowing",
    "bow_tie",
]


@dataclass(frozen=True)
class Protocol:
    """The tilt protocol (module docstring): tilts (deg), azimuths (deg), lighting, head radius."""

    tilts: tuple[float, ...] = (0.0, 5.0, 10.0, 15.0, 20.0)
    azimuths: tuple[float, ...] = (0.0, 22.5)
    lighting: str = "iso"
    head_radius_deg: float = HEAD_RADIUS_DEG
    size: int = 80
    wavelengths: int = 8

    def views(self) -> list[tuple[float, float]]:
        """Distinct (tilt, azimuth) pairs: face-up once, every other tilt at every azimuth."""
        out: list[tuple[float, float]] = []
        for t in self.tilts:
            for a in self.azimuths if t != 0 else self.azimuths[:1]:
                out.append((float(t), float(a)))
        return out


PROTOCOL = Protocol()


def tilted_views(stone: dict, protocol: Protocol = PROTOCOL, *, device=None, frame_mm=None):
    """Render ``stone`` at each view of ``protocol``: a list of ((tilt, azimuth), Image)."""
    from ..pipelines.render import render
    from ..scene.load import Scene

    out = []
    for t, a in protocol.views():
        data = face_up_scene(
            stone,
            lighting=protocol.lighting,
            head_radius_deg=protocol.head_radius_deg,
            tilt_deg=t,
            azimuth_deg=a,
            size=protocol.size,
            wavelengths=protocol.wavelengths,
            frame_mm=frame_mm,
        )
        out.append(((t, a), render(Scene.from_dict(data), device=device)))
    return out


def tilted_light_return(stone: dict, protocol: Protocol = PROTOCOL, *, device=None, frame_mm=None) -> dict:
    """The protocol's light return of ``stone`` (``light_return``: the mean over its views) and,
    averaged the same way, ``contrast`` and ``extinction``; ``per_view``: rows of (tilt,
    azimuth, light_return, contrast, extinction); ``renders``: the number of renders."""
    rows = []
    for (t, a), img in tilted_views(stone, protocol, device=device, frame_mm=frame_mm):
        rows.append(
            (
                t,
                a,
                wm.light_return(img.xyz, img.alpha),
                contrast(img.xyz, img.alpha),
                extinction(img.xyz, img.alpha),
            )
        )
    arr = np.array([r[2:] for r in rows])
    return {
        "light_return": float(arr[:, 0].mean()),
        "contrast": float(arr[:, 1].mean()),
        "extinction": float(arr[:, 2].mean()),
        "per_view": rows,
        "renders": len(rows),
    }


def _y_alpha(xyz, alpha):
    x = np.asarray(xyz, dtype=np.float64)
    a = np.ones(x.shape[:-1]) if alpha is None else np.asarray(alpha, dtype=np.float64)
    if x.shape[-1:] != (3,) or a.shape != x.shape[:-1]:
        raise InputError("xyz must be (H, W, 3) and alpha (H, W)", field="xyz", value=(x.shape, a.shape))
    return np.maximum(x[..., 1], 0.0), a


def contrast(xyz, alpha=None) -> float:
    """Coefficient of variation of the stone's luminance (module docstring)."""
    y, a = _y_alpha(xyz, alpha)
    w = a.sum()
    if w <= 0:
        return 0.0
    m = (a * y).sum() / w
    if m <= 0:
        return 0.0
    return float(np.sqrt((a * (y - m) ** 2).sum() / w) / m)


def extinction(xyz, alpha=None, *, threshold: float = 0.15, white_y: float = 1.0) -> float:
    """Fraction of the stone's area darker than ``threshold`` x ``white_y`` (module docstring)."""
    if not 0 < threshold < 1:
        raise InputError("must be in (0, 1)", field="threshold", value=threshold)
    y, a = _y_alpha(xyz, alpha)
    w = a.sum()
    return float((a * (y < threshold * white_y)).sum() / w) if w > 0 else 0.0


def windowing(bands) -> float:
    """Fraction of the stone's area that sees mostly through (module docstring); ``bands`` from
    :func:`warpoptics.grading.scopes.direction_bands`."""
    tot = bands.bands.sum(axis=-1) + bands.leak
    see_through = bands.leak > 0.5 * np.where(tot > 0, tot, np.inf)
    w = bands.alpha.sum()
    return float((bands.alpha * see_through).sum() / w) if w > 0 else 0.0


def bow_tie(xyz, alpha=None, *, band: float = 0.25, long_axis: str = "y") -> float:
    """Bow-tie darkness of an elongated stone seen face-up (module docstring); ``long_axis``: the
    image axis along which the stone is long ("x" or "y")."""
    if long_axis not in ("x", "y"):
        raise InputError("must be x or y", field="long_axis", value=long_axis)
    if not 0 < band < 1:
        raise InputError("must be in (0, 1)", field="band", value=band)
    y, a = _y_alpha(xyz, alpha)
    if long_axis == "x":
        y, a = y.T, a.T
    rows = np.nonzero(a.sum(axis=1) > 0)[0]
    if rows.size == 0:
        return 0.0
    c = 0.5 * (rows[0] + rows[-1])
    half = 0.5 * band * (rows[-1] - rows[0] + 1)
    r = np.arange(y.shape[0])[:, None]
    m = (np.abs(r - c) <= half) * a
    whole = (a * y).sum() / a.sum()
    if whole <= 0 or m.sum() <= 0:
        return 0.0
    return float(1.0 - ((m * y).sum() / m.sum()) / whole)
