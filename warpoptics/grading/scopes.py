"""Scope views of cut grading: where the light a stone returns comes from.

Every scope view here is a *direction-band decomposition* of the face-up image: the luminance
Y_k(p) that pixel p receives from the environment directions whose angle from the observer's axis
(+z, the zenith of a face-up stone) lies in a band [e_k, e_k+1), and the *leakage* Y_leak(p) it
receives from below the girdle plane.  Renders under the uniform ``dome`` with a head cone of
radius e (``head_radius``) return Y(p; e) = light from [e, 90 deg); a uniform ``constant`` sphere
returns everything; so, exactly and linearly (the transport is linear in the light),

    Y_k = Y(e_k) - Y(e_k+1),   Y_leak = Y_constant - Y(0).

(:func:`direction_bands`).  The stone is rendered without dispersion by default (a constant index
n_D), so one path tree serves the whole spectrum and the bands do not depend on colour sampling;
a clear stone then conserves energy per pixel: sum_k Y_k + Y_leak = Y_constant = 1 - absorption.

- **ASET** (AGS Laboratories' Angular Spectrum Evaluation Tool; Sasian et al. 2007): red = light
  from 45-90 deg above the girdle plane (the brightest, most direct light), green = 0-45 deg above
  it (less intense light), blue = the observer's obstruction (light from the cone about the
  viewing axis that the observer's head blocks: contrast), and black/white = leakage (light from
  below the girdle plane, which in the instrument passes through the stone).  Zone angles from
  the zenith: blue [0, r_head), red [r_head, 45), green [45, 90), leakage beyond 90.  Pixels are
  shown as the mix of the zone colours weighted by each zone's share, leakage white.
- **Ideal Scope** (G. Holloway's red-reflector viewer): light from the red reflector around the
  viewing hole, [r_hole, 45 deg) from the axis, shows red, the hole black, light from lower angles
  [45, 90) dark grey (the scope's sides), and leakage white (the back-lit stone lets it through).
- **Hearts & Arrows** viewer: a dark cone of ``viewer_radius_deg`` about the axis (the viewer's
  dark top) over a bright surround; the pavilion mains of a well-made brilliant reflect the dark
  cone as 8 arrows face-up and, seen from the pavilion side (:func:`hearts_and_arrows` with
  ``face_down=True``), as 8 hearts.  :func:`count_dark_lobes` counts them on a ring of the image
  and :func:`rotational_asymmetry` measures how far the pattern is from 8-fold symmetry.

References:
    J. Sasian, J. Quick, J. Sheffield, J. Caudill, P. Yantzer, "Evaluation of brilliance, fire,
    and scintillation in round brilliant gemstones", Optical Engineering 46(9), 093604 (2007)
    (ASET zones, observer at 25 cm, head obstruction).  AGS Laboratories, "ASET" and "AGS Light
    Performance" grading documentation (red 45-90 deg, green 0-45 deg, blue: observer
    obstruction, white/black: leakage).  G. Holloway, "The Ideal-Scope" (idealscope.com).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .presets import HEAD_RADIUS_DEG, face_up_scene

__all__ = [
    "ASET_EDGES_DEG",
    "ASET_COLORS",
    "Bands",
    "direction_bands",
    "aset",
    "ideal_scope",
    "hearts_and_arrows",
    "ring_profile",
    "count_dark_lobes",
    "rotational_asymmetry",
]

#: ASET zone boundaries, degrees from the viewing axis (AGS: red 45-90 deg above the girdle plane)
ASET_EDGES_DEG = (45.0, 90.0)
#: display colours (linear sRGB) of the ASET zones and of leakage
ASET_COLORS = {
    "blue": (0.0, 0.0, 1.0),
    "red": (1.0, 0.0, 0.0),
    "green": (0.0, 1.0, 0.0),
    "leak": (1.0, 1.0, 1.0),
}


@dataclass(frozen=True)
class Bands:
    """Face-up luminance per direction band: ``bands[..., k]`` (H, W, K) from the zenith-angle band
    [edges[k], edges[k+1]) in degrees (edges end at 90), ``leak`` (H, W) from below the girdle
    plane, ``alpha`` (H, W) the stone's coverage, ``renders`` the number of renders spent."""

    edges: tuple[float, ...]
    bands: np.ndarray
    leak: np.ndarray
    alpha: np.ndarray
    renders: int

    def fractions(self, mask=None) -> dict[str, float]:
        """Alpha-weighted share of each band and of leakage in the stone's light (within ``mask``,
        a boolean (H, W) region, default the whole stone): ``band0..``, ``leak``; they sum to 1."""
        w = self.alpha if mask is None else self.alpha * np.asarray(mask, dtype=np.float64)
        parts = [(w * self.bands[..., k]).sum() for k in range(self.bands.shape[-1])]
        parts.append((w * self.leak).sum())
        tot = float(sum(parts))
        if tot <= 0:
            return {**{f"band{k}": 0.0 for k in range(len(parts) - 1)}, "leak": 0.0}
        out = {f"band{k}": float(v / tot) for k, v in enumerate(parts[:-1])}
        out["leak"] = float(parts[-1] / tot)
        return out


def _stone_scene(stone, *, dispersive: bool) -> dict:
    ob = dict(stone)
    if not dispersive:
        from ..materials import material_from_spec

        mat = material_from_spec(ob.get("material", "diamond"))
        n_d = float(np.real(np.asarray(mat.n(np.array([589.3])))).ravel()[0])  # type: ignore[attr-defined]
        ob["material"] = {"cauchy": [n_d]}
    return ob


def direction_bands(
    stone: dict,
    edges_deg: Sequence[float],
    *,
    face_down: bool = False,
    tilt_deg: float = 0.0,
    azimuth_deg: float = 0.0,
    size: int = 96,
    dispersive: bool = False,
    wavelengths: int = 4,
    frame_mm: float | None = None,
    device=None,
) -> Bands:
    """The stone's face-up (or, ``face_down``, pavilion-up) light split by the angle of its
    source from the observer's axis (module docstring).  ``edges_deg``: increasing band edges in
    [0, 90) degrees; the first band starts at ``edges_deg[0]`` (give 0 to include the axis) and the
    last ends at 90.  Costs len(edges) + 1 renders (one per edge, one under a uniform sphere)."""
    from ..pipelines.render import render
    from ..scene.load import Scene

    e = [float(x) for x in edges_deg]
    if not e or any(not 0.0 <= x < 90.0 for x in e) or any(b <= a for a, b in zip(e, e[1:], strict=False)):
        raise InputError("band edges must increase within [0, 90) degrees", field="edges", value=list(e))
    if e[0] != 0.0:
        raise InputError("the first band edge must be 0 (the viewing axis)", field="edges", value=e[0])
    ob = _stone_scene(stone, dispersive=dispersive)
    if face_down:
        ob["rotation"] = [180.0, 0.0, 0.0]
    base = face_up_scene(
        ob, tilt_deg=tilt_deg, azimuth_deg=azimuth_deg, size=size, wavelengths=wavelengths, frame_mm=frame_mm
    )
    if face_down:  # face_up_scene set the tilt rotation; the flip comes first
        base["object"][0]["rotation"] = [180.0 + float(tilt_deg), 0.0, float(azimuth_deg)]
    ys = []
    alpha = None
    for edge in [*e, None]:
        data = dict(base)
        if edge is None:
            data["light"] = [{"type": "constant", "intensity": 1.0}]
        else:
            data["light"] = [{"type": "environment", "map": "dome", "head_radius": edge}]
        img = render(Scene.from_dict(data), device=device)
        ys.append(np.maximum(np.asarray(img.xyz[..., 1], dtype=np.float64), 0.0))
        alpha = np.asarray(img.alpha, dtype=np.float64)
    # Y(e_k) - Y(e_k+1); the last band ends at the horizon (Y beyond 90 deg from a dome is 0)
    cum = ys[:-1] + [np.zeros_like(ys[0])]
    bands = np.stack([np.maximum(cum[k] - cum[k + 1], 0.0) for k in range(len(e))], axis=-1)
    leak = np.maximum(ys[-1] - ys[0], 0.0)
    assert alpha is not None
    return Bands(edges=tuple(e), bands=bands, leak=leak, alpha=alpha, renders=len(ys))


def _compose(bands: Bands, colors: Sequence[Sequence[float]], leak_color) -> np.ndarray:
    tot = bands.bands.sum(axis=-1) + bands.leak
    safe = np.where(tot > 0, tot, 1.0)
    rgb = np.zeros(bands.leak.shape + (3,))
    for k, c in enumerate(colors):
        rgb += (bands.bands[..., k] / safe)[..., None] * np.asarray(c, dtype=np.float64)
    rgb += (bands.leak / safe)[..., None] * np.asarray(leak_color, dtype=np.float64)
    return np.clip(rgb * bands.alpha[..., None], 0.0, 1.0)


def aset(stone: dict, *, head_radius_deg: float = HEAD_RADIUS_DEG, size: int = 96, **kw):
    """ASET image (H, W, 3) display sRGB-linear in [0, 1] and the zone fractions ``{"blue",
    "red", "green", "leak"}`` of the whole stone, plus ``"leak_centre"``: the leakage share within
    the central 30 % of the diameter (under the table, the pavilion centre), and the
    :class:`Bands` (module docstring: zones and source)."""
    if not 0.0 < head_radius_deg < ASET_EDGES_DEG[0]:
        raise InputError("must be in (0, 45) degrees", field="head_radius", value=head_radius_deg)
    b = direction_bands(stone, (0.0, head_radius_deg, ASET_EDGES_DEG[0]), size=size, **kw)
    img = _compose(b, [ASET_COLORS["blue"], ASET_COLORS["red"], ASET_COLORS["green"]], ASET_COLORS["leak"])
    f = b.fractions()
    h, w = b.alpha.shape
    yy, xx = np.mgrid[0:h, 0:w]
    r = np.hypot(xx - (w - 1) / 2, yy - (h - 1) / 2) / (0.5 * w / 1.08)  # in units of the girdle radius
    centre = b.fractions(r < 0.3)
    zones = {
        "blue": f["band0"],
        "red": f["band1"],
        "green": f["band2"],
        "leak": f["leak"],
        "leak_centre": centre["leak"],
    }
    return img, zones, b


def ideal_scope(stone: dict, *, hole_deg: float = 5.0, size: int = 96, **kw):
    """Ideal Scope image (H, W, 3) in [0, 1] (module docstring) and its fractions ``{"hole",
    "red", "side", "leak"}``."""
    b = direction_bands(stone, (0.0, hole_deg, 45.0), size=size, **kw)
    img = _compose(b, [(0.0, 0.0, 0.0), (0.9, 0.05, 0.1), (0.2, 0.2, 0.2)], (1.0, 1.0, 1.0))
    f = b.fractions()
    return img, {"hole": f["band0"], "red": f["band1"], "side": f["band2"], "leak": f["leak"]}, b


def hearts_and_arrows(
    stone: dict, *, face_down: bool = False, viewer_radius_deg: float = 30.0, size: int = 128, **kw
):
    """Hearts & Arrows viewer image: luminance (H, W) of the light from outside the viewer's dark
    cone (``viewer_radius_deg`` about the axis), face-up (arrows) or ``face_down`` (hearts),
    relative to the stone's total (so a dark lobe is a region that sees the dark cone), and the
    :class:`Bands`."""
    b = direction_bands(stone, (0.0, viewer_radius_deg), size=size, face_down=face_down, **kw)
    bright = b.bands[..., 1]
    return bright * b.alpha, b


def ring_profile(image, radius: float, *, samples: int = 720, centre=None) -> np.ndarray:
    """Values of a 2-D ``image`` on a circle of ``radius`` pixels about ``centre`` (default the
    image centre), at ``samples`` azimuths 360 k / samples degrees counter-clockwise from image
    right (bilinear)."""
    from scipy.ndimage import map_coordinates

    a = np.asarray(image, dtype=np.float64)
    h, w = a.shape
    cy, cx = ((h - 1) / 2, (w - 1) / 2) if centre is None else centre
    phi = 2 * np.pi * np.arange(samples) / samples
    rows = cy - radius * np.sin(phi)
    cols = cx + radius * np.cos(phi)
    return map_coordinates(a, [rows, cols], order=1, mode="nearest")


def count_dark_lobes(profile, *, threshold: float | None = None) -> int:
    """Number of dark runs on a closed ring profile (:func:`ring_profile`): maximal circular runs
    below ``threshold`` (default halfway between the profile's 10th and 90th percentiles)."""
    p = np.asarray(profile, dtype=np.float64)
    t = 0.5 * (np.percentile(p, 10) + np.percentile(p, 90)) if threshold is None else threshold
    dark = p < t
    if dark.all() or not dark.any():
        return 0
    # runs on a circle: count dark samples whose predecessor (circularly) is bright
    return int(np.sum(dark & ~np.roll(dark, 1)))


def rotational_asymmetry(image, *, fold: int = 8, radii: Sequence[float] | None = None, samples: int = 720):
    """How far an image is from ``fold``-fold rotational symmetry about its centre:
    A = sum |I(r, phi) - I(r, phi + 360/fold)| / sum (I(r, phi) + I(r, phi + 360/fold)) over rings
    (``radii`` in pixels, default 20 rings over 10-90 % of the half-width), in [0, 1]; 0 for an
    exactly symmetric pattern.  ``samples`` must be a multiple of ``fold``."""
    a = np.asarray(image, dtype=np.float64)
    if samples % fold:
        raise InputError("samples must be a multiple of fold", field="samples", value=samples)
    half = 0.5 * min(a.shape)
    rr = np.linspace(0.1 * half, 0.9 * half, 20) if radii is None else radii
    num = den = 0.0
    shift = samples // fold
    for r in rr:
        p = ring_profile(a, float(r), samples=samples)
        q = np.roll(p, -shift)
        num += float(np.abs(p - q).sum())
        den += float((p + q).sum())
    return num / den if den > 0 else 0.0
