"""Polarization views of a rendered image, computed from its per-channel Stokes image (no re-render).

A render keeps, per pixel, the Stokes vector of each of X, Y and Z in the camera frame
(``Image.stokes_xyz``, x = image right, y = image up).  Every view here is an ideal optical
element put between the image and the eye, applied with the Mueller matrix of
:func:`warpoptics.optics.polarizer.mueller_linear_polarizer` (one place) to each channel; the
result is again an :class:`~warpoptics.film.image.Image` (XYZ = S0 of each channel behind the
element), so views compose and save like renders.

- ``analyzer`` (angle θ): an ideal linear polarizer with its transmission axis at θ degrees from
  image right toward image up (counter-clockwise on the image).  Unpolarized light loses half.
- ``polariscope``: crossed polarizers.  The *illumination* must be polarized: a render with
  ``[[light]] polarizer = θp`` (an ideal sheet polarizer in front of the environment, facing the
  camera; :func:`warpoptics.optics.polarizer.sheet_polarizer_coherency` at each path's light
  end, so each path's Jones matrix M carries the polarized source as ``M ρ_in M†``).  The view
  is the analyzer at θp + 90° (``polariscope:parallel``: at θp).  With nothing in view the
  crossed field is black; an isotropic stone stays nearly dark (only the Fresnel/TIR phase
  changes at oblique facets turn the polarization); a birefringent stone lights up except where
  its optic axis lies along a polarizer direction or toward the eye.
- ``dichroscope`` (angle θ, default 0): the analyzer at θ and at θ + 90° side by side (left,
  right), as the calcite rhomb of a gemologist's dichroscope shows two orthogonally polarized
  images of the same window: a pleochroic stone shows two colours.  In a biaxial (trichroic)
  stone the two windows are the two eigenwaves of the viewing direction when θ lies along the
  D of one of them: :func:`eigenwave_angle` gives that θ (biaxial: fast wave left) from the stone's
  principal axes and the camera, ``dichroscope:auto`` on the command line (uniaxial stones: the
  o-wave's D, perpendicular to the optic axis).  Along a principal axis the windows show the
  colours of the other two principal spectra; looking along X, Y and Z shows all three.

Why the polariscope's polarizer is a render-time source and not a Mueller film, and why a
dichroscope wants unpolarized light: docs/design/polarization_views.md.

References:
    D. Goldstein, *Polarized Light*, 2nd ed. (2003), §5.3 (Mueller matrices).  R. Webster,
    *Gems*, 5th ed. (1994), ch. 34 (polariscope, dichroscope).  S. Guy, C. Soler, ACM TOG 23(3)
    2004, §3.2 (pleochroism), eq. 12 (coherency along a path).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import InputError
from ..optics.polarizer import analyze, sheet_absorbing_axis

__all__ = [
    "VIEW_KINDS",
    "parse_view",
    "apply_view",
    "analyzer",
    "polariscope",
    "dichroscope",
    "polarizer_world_axis",
    "eigenwave_angle",
]

VIEW_KINDS = ("none", "analyzer", "polariscope", "dichroscope")


def parse_view(
    spec: str, angle: float | None = None, *, field: str = "--view"
) -> tuple[str, float | str | None]:
    """``"analyzer:30"`` -> ("analyzer", 30.0); ``"polariscope"`` / ``"polariscope:parallel"``;
    ``"dichroscope[:angle]"``, ``"dichroscope:auto"`` (-> ("dichroscope", "auto"): the caller that
    knows the stone and the camera resolves it with :func:`eigenwave_angle`); ``"none"``.
    ``angle`` (degrees) is used when the spec has none."""
    if not isinstance(spec, str) or not spec.strip():
        raise InputError("must be a view name", field=field, value=spec, allowed=", ".join(VIEW_KINDS))
    kind, _, arg = spec.strip().partition(":")
    kind = kind.strip().lower()
    if kind not in VIEW_KINDS:
        raise InputError(
            "unknown view",
            field=field,
            value=spec,
            allowed="none, analyzer:ANGLE, polariscope[:parallel], dichroscope[:ANGLE|auto]",
        )
    arg = arg.strip()
    if kind == "polariscope":
        if arg not in ("", "crossed", "parallel"):
            raise InputError(
                "unknown polariscope setting", field=field, value=spec, allowed="crossed, parallel"
            )
        return kind, arg or "crossed"
    if kind == "none":
        return kind, None
    if kind == "dichroscope" and arg.lower() == "auto":
        # the angle of the stone's fast eigenwave (eigenwave_angle), set by who knows the scene
        return kind, "auto"
    value = angle
    if arg:
        try:
            value = float(arg)
        except ValueError:
            raise InputError("the angle must be a number of degrees", field=field, value=spec) from None
    if kind == "analyzer" and value is None:
        raise InputError("the analyzer needs an angle, e.g. analyzer:30 (degrees)", field=field, value=spec)
    if value is not None and not math.isfinite(value):
        raise InputError("the angle must be finite", field=field, value=spec)
    if value is not None and abs(value) > 360.0:
        # cos(2θ) of a huge angle in float32 is NaN (1e308 gave NaN pixels with exit 0)
        raise InputError("the angle is out of range", field=field, value=spec, allowed="-360 to 360 degrees")
    return kind, (0.0 if value is None else float(value))


def _stokes_xyz(image) -> np.ndarray:
    if image.stokes_xyz is None:
        raise InputError(
            "this image has no per-channel Stokes vectors (render it with warpoptics.render, or "
            "load an EXR written by Image.save)",
            field="view",
        )
    return np.asarray(image.stokes_xyz, dtype=np.float64)


def _from_stokes(image, s_xyz: np.ndarray, alpha: np.ndarray, view: str):
    stats = dict(image.stats)
    stats["view"] = view
    return dataclasses.replace(
        image,
        xyz=np.ascontiguousarray(s_xyz[..., 0]),
        stokes=np.ascontiguousarray(s_xyz[..., 1, :]),
        alpha=alpha,
        stokes_xyz=s_xyz,
        stats=stats,
    )


def analyzer(image, angle: float, *, device=None):
    """The image seen through an ideal linear analyzer at ``angle`` degrees (from image right
    toward image up): XYZ = S0 of each channel after the polarizer's Mueller matrix."""
    s = analyze(_stokes_xyz(image), float(angle), device=device)
    return _from_stokes(image, s, image.alpha, f"analyzer:{float(angle):g}")


def polariscope(image, *, parallel: bool = False, device=None):
    """Crossed (or ``parallel``) polarizers: the analyzer at the light's polarizer angle + 90°
    (+ 0°).  Needs an image rendered with polarized light (``[[light]] polarizer = angle``)."""
    if image.source_polarizer is None:
        raise InputError(
            "a polariscope view needs polarized light: render with [[light]] polarizer = ANGLE "
            "(degrees), e.g. --set light.0.polarizer=45",
            field="view",
            value="polariscope",
        )
    out = analyzer(image, image.source_polarizer + (0.0 if parallel else 90.0), device=device)
    out.stats["view"] = "polariscope:" + ("parallel" if parallel else "crossed")
    return out


def dichroscope(image, angle: float = 0.0, *, gap: int | None = None, device=None):
    """Two images side by side: the analyzer at ``angle`` (left) and ``angle + 90`` (right),
    separated by ``gap`` black pixels (default width/40, at least 2)."""
    s = _stokes_xyz(image)
    h, w = s.shape[:2]
    g = max(2, w // 40) if gap is None else int(gap)
    if g < 0:
        raise InputError("must be >= 0", field="gap", value=gap)
    left = analyze(s, float(angle), device=device)
    right = analyze(s, float(angle) + 90.0, device=device)
    pad = np.zeros((h, g, 3, 4))
    s_out = np.concatenate([left, pad, right], axis=1)
    alpha = np.concatenate([image.alpha, np.zeros((h, g)), image.alpha], axis=1)
    return _from_stokes(image, s_out, alpha, f"dichroscope:{float(angle):g}")


def apply_view(image, kind: str | None, angle: float | None = None, *, device=None):
    """Apply a view by name (``"analyzer:30"``, ``"polariscope"``, ``"dichroscope"``, ``"none"``)."""
    if kind is None:
        return image
    k, arg = parse_view(kind, angle)
    if k == "none":
        return image
    if k == "analyzer":
        return analyzer(image, arg, device=device)
    if k == "polariscope":
        return polariscope(image, parallel=arg == "parallel", device=device)
    if arg == "auto":
        raise InputError(
            "dichroscope:auto needs the stone and the camera: `warpoptics render --view "
            "dichroscope:auto`, or dichroscope(image, eigenwave_angle(...)) in Python",
            field="view",
            value=kind,
        )
    return dichroscope(image, arg, device=device)


def polarizer_world_axis(right, up, angle_deg: float) -> np.ndarray:
    """The absorbing axis (world, unit) of the light's sheet polarizer: the sheet faces the camera
    (``right``, ``up``: the camera's world axes), its transmission axis at ``angle_deg`` on the image."""
    return sheet_absorbing_axis(
        np.asarray(right, dtype=np.float64), np.asarray(up, dtype=np.float64), angle_deg
    )


def eigenwave_angle(material, direction, right, up, *, wavelength_nm: float = 550.0, device=None) -> float:
    """The analyzer angle (degrees, from image ``right`` toward image ``up``) along the D vector of
    the fast eigenwave travelling along ``direction`` (world, toward the eye's line of sight into
    the stone) in ``material``: a :class:`~warpoptics.materials.Biaxial` with world
    ``crystal_axes`` (the D from :func:`warpoptics.optics.biaxial.principal_d`), or a
    :class:`~warpoptics.materials.Uniaxial` (the o-wave: D perpendicular to the optic axis and
    the direction; fast in a positive crystal, slow in a negative one).  A dichroscope at this
    angle shows that wave left, the other right.
    Isotropic materials, and a wave normal along an optic axis, have no preferred D: 0.0."""
    from ..materials import Biaxial, Uniaxial
    from ..optics.biaxial import principal_d

    s = np.asarray(direction, dtype=np.float64)
    s = s / np.linalg.norm(s)
    r = np.asarray(right, dtype=np.float64)
    u = np.asarray(up, dtype=np.float64)
    if isinstance(material, Biaxial):
        axes = material.crystal_axes
        n = material.n(wavelength_nm, device=device)
        _, d_local = principal_d(s, 0, axes, n[0], n[1], n[2], device=device)
        d = np.asarray(d_local, dtype=np.float64) @ axes
    elif isinstance(material, Uniaxial):
        d = np.cross(np.asarray(material.optic_axis, dtype=np.float64), s)
    else:
        return 0.0
    x, y = float(d @ r), float(d @ u)
    if math.hypot(x, y) < 1e-9:
        return 0.0
    # an analyzer axis is a line: fold into [0, 180)
    return float(np.degrees(np.arctan2(y, x)) % 180.0)
