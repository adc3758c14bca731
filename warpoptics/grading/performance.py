"""Light-performance metrics over a tilt protocol with the observer's head (after GIA and AGS).

The protocol (:data:`PROTOCOL`, :func:`tilted_light_return`): the stone is seen by an observer
at 250 mm on its axis (:func:`~warpoptics.grading.presets.face_up_scene`) under GemRay's ISO
lighting (the uniform D65 ``dome``) from which the observer's head blocks a cone of
:data:`~warpoptics.grading.presets.HEAD_RADIUS_DEG` (10 deg) about the line of sight.  The stone
is rocked face-up and by 5, 10, 15 and 20 deg about two horizontal axes (across a pavilion main
and between two mains); the head stays with the observer.  Light return
(:func:`warpoptics.metrics.light_return`) is the plain mean over the 9 views.

Fire and scintillation over the same tilts (:func:`warpoptics.sweep.grading.light_performance`,
:meth:`Protocol.view_rotations`): each view is rendered again under the ``spots`` lighting;
*fire* is :func:`warpoptics.metrics.fire` of that view and *scintillation* is
:func:`warpoptics.metrics.scintillation` between it and the stone turned a further
``scintillation_step_deg`` (2 deg); both are plain means over the views.  A view costs 3
renders; ``fire=False`` keeps 1.

Further metrics of one view (functions of a render's ``xyz`` and ``alpha``, unitless):
:func:`contrast` (coefficient of variation of the stone's luminance), :func:`extinction` (area
fraction darker than ``threshold`` of the dome's white), :func:`windowing` (area fraction lit
mostly from below the girdle plane), :func:`brightness_map` (bright / medium / dark classes,
relative to the dome or, for coloured stones, to the stone's 95th-percentile luminance) and
:func:`bow_tie` (the darkness of a band across an elongated stone's centre).

Where the protocol and metrics follow GIA (Hemphill et al. 1998, Reinitz et al. 2001, Moses et
al. 2004) and AGS (Sasian et al. 2007), and where they differ: docs/design/grading_metrics.md.
References: see :mod:`warpoptics.grading.presets` and :mod:`warpoptics.grading.scopes`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import metrics as wm
from ..errors import InputError
from .presets import HEAD_RADIUS_DEG, face_up_scene, tilt_rotation

__all__ = [
    "Protocol",
    "PROTOCOL",
    "tilted_views",
    "tilted_light_return",
    "contrast",
    "extinction",
    "windowing",
    "bow_tie",
    "brightness_map",
    "BRIGHTNESS_MAP_COLORS",
    "average_views",
]


#: the most (tilt, azimuth) views a protocol may have (each is rendered once per lighting)
MAX_PROTOCOL_VIEWS = 500


@dataclass(frozen=True)
class Protocol:
    """The tilt protocol (module docstring): tilts (deg), azimuths (deg), lighting, head radius."""

    tilts: tuple[float, ...] = (0.0, 5.0, 10.0, 15.0, 20.0)
    azimuths: tuple[float, ...] = (0.0, 22.5)
    lighting: str = "iso"
    head_radius_deg: float = HEAD_RADIUS_DEG
    size: int = 80
    wavelengths: int = 8
    fire_lighting: str = "spots"
    scintillation_step_deg: float = 2.0

    def __post_init__(self):
        if not self.tilts or any(not -80.0 <= t <= 80.0 for t in self.tilts):
            raise InputError("tilts must be in [-80, 80] degrees", field="tilts", value=self.tilts)
        if not self.azimuths:
            raise InputError("needs at least one azimuth", field="azimuths", value=self.azimuths)
        if not 0.0 < self.scintillation_step_deg <= 10.0:
            raise InputError(
                "must be in (0, 10] degrees", field="scintillation_step", value=self.scintillation_step_deg
            )
        if self.size < 4 or self.wavelengths < 1:
            raise InputError(
                "size >= 4 and wavelengths >= 1", field="size", value=(self.size, self.wavelengths)
            )
        for name in ("tilts", "azimuths"):
            vals = [float(v) for v in getattr(self, name)]
            if not all(math.isfinite(v) for v in vals):
                raise InputError("must be finite", field=name, value=getattr(self, name))
            if len(set(vals)) != len(vals):
                raise InputError("lists a value twice", field=name, value=getattr(self, name))
        n = len(self.views())
        if n > MAX_PROTOCOL_VIEWS:
            raise InputError(
                f"gives {n:,} views ({len(self.tilts)} tilts x {len(self.azimuths)} azimuths), more than "
                f"{MAX_PROTOCOL_VIEWS}: take fewer tilts or azimuths",
                field="tilts",
            )

    def view_rotations(self) -> list[tuple[str, float, float, list[float]]]:
        """(name, tilt, azimuth, ``object.rotation``) of each view of :meth:`views`; names like
        ``t05_a22`` (tilt 5, azimuth 22.5), usable as sweep view names."""
        views = self.views()
        names = [f"t{t:02.0f}_a{a:02.0f}".replace("-", "m") for t, a in views]
        if len(set(names)) != len(names):  # fractional values the short names round together
            names = [f"t{t:g}_a{a:g}".replace("-", "m").replace(".", "p") for t, a in views]
        return [(name, t, a, tilt_rotation(t, a)) for name, (t, a) in zip(names, views, strict=True)]

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


#: display colours (linear sRGB) of :func:`brightness_map`'s classes
BRIGHTNESS_MAP_COLORS = {"bright": (1.0, 0.85, 0.1), "medium": (0.15, 0.45, 0.9), "dark": (0.6, 0.0, 0.0)}


def brightness_map(
    xyz,
    alpha=None,
    *,
    reference: str = "white",
    white_y: float = 1.0,
    bright: float = 0.5,
    dark: float = 0.15,
):
    """Brightness/contrast map of a face-up view (module docstring): ``(image, fractions,
    relative)``: ``image`` (H, W, 3) linear sRGB in [0, 1] (:data:`BRIGHTNESS_MAP_COLORS`, black
    off the stone, weighted by alpha), ``fractions`` ``{"bright", "medium", "dark"}`` of the
    stone's area (alpha-weighted, sum 1), ``relative`` (H, W) the pixels' luminance over the
    reference: ``white_y`` (``reference="white"``) or the stone's alpha-weighted 95th percentile
    of Y (``"stone"``, for coloured stones)."""
    if reference not in ("white", "stone"):
        raise InputError("unknown reference", field="reference", value=reference, allowed="white, stone")
    if not 0 < dark < bright:
        raise InputError("needs 0 < dark < bright", field="bright", value=(dark, bright))
    if not white_y > 0:
        raise InputError("must be > 0", field="white_y", value=white_y)
    y, a = _y_alpha(xyz, alpha)
    ref = float(white_y)
    if reference == "stone":
        on = a > 0
        if not on.any():
            raise InputError("the view shows no stone", field="alpha")
        order = np.argsort(y[on])
        cw = np.cumsum(a[on][order])
        ref = float(y[on][order][np.searchsorted(cw, 0.95 * cw[-1])])
        if not ref > 0:
            raise InputError("the stone is black in this view", field="xyz")
    rel = y / ref
    classes = {"bright": rel >= bright, "dark": rel < dark}
    classes["medium"] = ~(classes["bright"] | classes["dark"])
    w = a.sum()
    img = np.zeros(y.shape + (3,))
    fr = {}
    for k in ("bright", "medium", "dark"):
        img[classes[k]] = BRIGHTNESS_MAP_COLORS[k]
        fr[k] = float((a * classes[k]).sum() / w) if w > 0 else 0.0
    return np.clip(img * a[..., None], 0.0, 1.0), fr, rel


def average_views(per_view: list[dict[str, float]]) -> dict[str, float]:
    """The protocol's value of each metric: the plain mean over the views' dicts (module
    docstring); every view must carry the same keys."""
    if not per_view:
        raise InputError("no views to average", field="views")
    keys = set(per_view[0])
    if any(set(v) != keys for v in per_view):
        raise InputError(
            "views measure different metrics", field="views", value=[sorted(v) for v in per_view]
        )
    return {k: float(np.mean([v[k] for v in per_view])) for k in sorted(keys)}
