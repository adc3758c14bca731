"""Scope views of cut grading: where the light a stone returns comes from.

Every scope view is a *direction-band decomposition* of the face-up image: the luminance Y_k(p)
that pixel p receives from environment directions whose angle from the observer's axis (+z)
lies in a band [e_k, e_k+1), and the *leakage* Y_leak(p) from below the girdle plane.  Renders
under the ``dome`` with a head cone of radius e give Y(p; e), light from [e, 90 deg), and a
uniform ``constant`` sphere gives everything, so exactly (the transport is linear in the light)

    Y_k = Y(e_k) - Y(e_k+1),   Y_leak = Y_constant - Y(0)

(:func:`direction_bands`).  The stone is rendered without dispersion by default (a constant
index n_D), so one path tree serves the whole spectrum; a clear stone then conserves energy per
pixel: sum_k Y_k + Y_leak = 1 - absorption.

- **ASET** (Sasian et al. 2007): red = light from 45-90 deg above the girdle plane, green = 0-45
  deg, blue = the observer's obstruction, white/black = leakage.  :func:`aset` reports each
  zone's *energy* share (every path order, Fresnel partial reflections included) and the *area*
  share of the pixels a zone dominates (what a grader reads off the image), over the ``centre``
  (r < 0.3 girdle radii) and ``crown`` regions.
- **Ideal Scope** (G. Holloway): the red reflector [r_hole, 45 deg) red, the hole black, lower
  angles dark grey, leakage white.
- **Hearts & Arrows**: a dark cone of ``viewer_radius_deg`` over a bright surround; the mains of
  a well-made brilliant show 8 arrows face-up and 8 hearts face-down
  (:func:`hearts_and_arrows`); :func:`count_dark_lobes`, :func:`count_pattern` and
  :func:`rotational_asymmetry` measure the pattern.

The zones in detail and the hand-traced checks of the ASET figures (the Tolkowsky centre's
leakage energy without leakage area, deep pavilions): docs/design/scopes.md.

References: Sasian, Quick, Sheffield, Caudill & Yantzer, "Evaluation of brilliance, fire, and
scintillation in round brilliant gemstones", Opt. Eng. 46(9) 093604 (2007); AGS Laboratories,
ASET grading documentation; G. Holloway, "The Ideal-Scope".
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
    "LobeCount",
    "count_pattern",
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
    plane, ``alpha`` (H, W) the stone's coverage, ``renders`` the number of renders spent.  The
    values are the stone's light only, coverage included (a pixel half on the stone holds half its
    mean radiance there; the background the other half sees is removed)."""

    edges: tuple[float, ...]
    bands: np.ndarray
    leak: np.ndarray
    alpha: np.ndarray
    renders: int

    def fractions(self, mask=None) -> dict[str, float]:
        """Share of each band and of leakage in the stone's light (within ``mask``, a boolean
        (H, W) region, default the whole stone): ``band0..``, ``leak``; they sum to 1.  The values
        already carry each pixel's coverage (alpha x the stone's mean radiance in the pixel), so
        the pixels are summed unweighted."""
        w = (self.alpha > 0).astype(np.float64)
        if mask is not None:
            w = w * np.asarray(mask, dtype=np.float64)
        parts = [(w * self.bands[..., k]).sum() for k in range(self.bands.shape[-1])]
        parts.append((w * self.leak).sum())
        tot = float(sum(parts))
        if tot <= 0:
            return {**{f"band{k}": 0.0 for k in range(len(parts) - 1)}, "leak": 0.0}
        out = {f"band{k}": float(v / tot) for k, v in enumerate(parts[:-1])}
        out["leak"] = float(parts[-1] / tot)
        return out

    def dominant(self) -> np.ndarray:
        """Per pixel, the index of the zone with the largest energy: 0..K-1 the bands, K the
        leakage; -1 where the pixel gets no light (off the stone)."""
        e = np.concatenate([self.bands, self.leak[..., None]], axis=-1)
        return np.where(e.sum(axis=-1) > 0, np.argmax(e, axis=-1), -1)

    def areas(self, mask=None) -> dict[str, float]:
        """Alpha-weighted share of the stone's area (within ``mask``) that each band and the
        leakage dominate (:meth:`dominant`): ``band0..``, ``leak``; they sum to 1."""
        w = self.alpha if mask is None else self.alpha * np.asarray(mask, dtype=np.float64)
        dom = self.dominant()
        k = self.bands.shape[-1]
        tot = float((w * (dom >= 0)).sum())
        if tot <= 0:
            return {**{f"band{i}": 0.0 for i in range(k)}, "leak": 0.0}
        out = {f"band{i}": float((w * (dom == i)).sum() / tot) for i in range(k)}
        out["leak"] = float((w * (dom == k)).sum() / tot)
        return out

    def radius(self) -> np.ndarray:
        """Distance (H, W) of each pixel centre from the image centre in girdle radii, for the
        framing of :func:`~warpoptics.grading.presets.face_up_scene` (the half-width is 1.08 girdle
        radii at the girdle plane; the table, ~1 mm nearer the observer at 250 mm, is 0.4 % larger)."""
        h, w = self.alpha.shape
        yy, xx = np.mgrid[0:h, 0:w]
        return np.hypot(xx - (w - 1) / 2, yy - (h - 1) / 2) / (0.5 * w / 1.08)


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
    assert alpha is not None
    # A pixel's value is the mean over its sub-rays, which are jittered within the pixel: at the
    # girdle outline (alpha < 1) the rays that miss the stone see the environment straight below
    # the camera, Y = 1 under the constant light and 0 under the dome (black below the horizon).
    # That background is not light through the stone: remove it from the constant render, so
    # that every band and the leakage hold the stone's light alone (alpha x its mean radiance).
    ys[-1] = ys[-1] - (1.0 - alpha)
    # Y(e_k) - Y(e_k+1); the last band ends at the horizon (Y beyond 90 deg from a dome is 0)
    cum = ys[:-1] + [np.zeros_like(ys[0])]
    bands = np.stack([np.maximum(cum[k] - cum[k + 1], 0.0) for k in range(len(e))], axis=-1)
    leak = np.maximum(ys[-1] - ys[0], 0.0)
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
    """ASET image (H, W, 3) display sRGB-linear in [0, 1], the zone fractions and the
    :class:`Bands` (module docstring: zones, energy and area fractions, regions, sources).

    Fractions: energy shares ``blue``, ``red``, ``green``, ``leak`` of the whole stone and their
    area shares ``area_blue`` .. ``area_leak``; for the ``centre`` region (r < 0.3 girdle radii)
    ``leak_centre`` and ``area_leak_centre``, and, for stones whose table is known (the
    ``table`` key, default 0.53 for ``round_brilliant``), the ``crown`` region (r >= table)
    ``leak_crown`` and ``area_leak_crown``.  The regions are image regions about the image centre
    (a tilted stone's table centre moves by crown height x sin(tilt): 0.1 girdle radii at 20 deg)."""
    if not 0.0 < head_radius_deg < ASET_EDGES_DEG[0]:
        raise InputError("must be in (0, 45) degrees", field="head_radius", value=head_radius_deg)
    b = direction_bands(stone, (0.0, head_radius_deg, ASET_EDGES_DEG[0]), size=size, **kw)
    img = _compose(b, [ASET_COLORS["blue"], ASET_COLORS["red"], ASET_COLORS["green"]], ASET_COLORS["leak"])
    names = {"band0": "blue", "band1": "red", "band2": "green", "leak": "leak"}
    f, a = b.fractions(), b.areas()
    zones = {names[k]: v for k, v in f.items()} | {f"area_{names[k]}": v for k, v in a.items()}
    r = b.radius()
    zones["leak_centre"] = b.fractions(r < 0.3)["leak"]
    zones["area_leak_centre"] = b.areas(r < 0.3)["leak"]
    table = stone.get("table", 0.53 if stone.get("shape") == "round_brilliant" else None)
    if table is not None:
        # the table's corners lie at r = table (table width corner to corner / diameter)
        zones["leak_crown"] = b.fractions(r >= float(table))["leak"]
        zones["area_leak_crown"] = b.areas(r >= float(table))["leak"]
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


def count_dark_lobes(profile, *, threshold: float | None = None, max_harmonic: int | None = None) -> int:
    """Number of dark runs on a closed ring profile (:func:`ring_profile`): maximal circular runs
    below ``threshold`` (default halfway between the profile's 10th and 90th percentiles).  With
    ``max_harmonic`` the profile is first low-passed to its angular harmonics 0..max_harmonic
    (features narrower than about 360 / (2 max_harmonic) deg, such as a facet edge a pixel wide
    or the one-sample-per-pixel jitter, then neither split a lobe nor count as one)."""
    p = np.asarray(profile, dtype=np.float64)
    if max_harmonic is not None:
        c = np.fft.rfft(p)
        c[int(max_harmonic) + 1 :] = 0.0
        p = np.fft.irfft(c, n=len(p))
    t = 0.5 * (np.percentile(p, 10) + np.percentile(p, 90)) if threshold is None else threshold
    dark = p < t
    if dark.all() or not dark.any():
        return 0
    # runs on a circle: count dark samples whose predecessor (circularly) is bright
    return int(np.sum(dark & ~np.roll(dark, 1)))


@dataclass(frozen=True)
class LobeCount:
    """The Hearts & Arrows count of :func:`count_pattern`: ``count`` the number of hearts or
    arrows (``fold``, e.g. 8) when the pattern is intact, else None; ``per_ring`` the dark-lobe
    counts of the rings; ``mode`` their most frequent value; ``agreement`` the share of rings at
    ``mode``; ``verdict`` ``"intact"`` or why the pattern is broken."""

    count: int | None
    per_ring: tuple[int, ...]
    mode: int
    agreement: float
    verdict: str


#: ring radii (girdle radii) on which hearts (face-down) and arrows (face-up) are counted: the
#: hearts lie in the inner pavilion around the culet, the arrows' shafts run from the table out
HEART_RINGS = tuple(float(x) for x in np.linspace(0.12, 0.3, 7))
ARROW_RINGS = tuple(float(x) for x in np.linspace(0.15, 0.45, 9))


def count_pattern(image, *, face_down: bool, fold: int = 8, min_agreement: float = 2.0 / 3.0) -> LobeCount:
    """Count the hearts (``face_down``) or arrows of a Hearts & Arrows image (:func:`hearts_and_arrows`,
    framed by :func:`~warpoptics.grading.presets.face_up_scene`): the dark lobes on each of
    :data:`HEART_RINGS` / :data:`ARROW_RINGS` (:func:`count_dark_lobes`).  A Hearts & Arrows
    pattern is ``fold`` lobes, one per pavilion main: the count is reported only when ``fold`` is
    the lobe count on at least ``min_agreement`` of the rings (default a two-thirds majority).
    Anything else is a broken pattern, reported with ``count`` None rather than as that many hearts
    (the deep 43 deg stone's outer heart rings read 16 lobes, two per main: 8 lobes on 3-4 of the
    7 rings at 96-256 px, where the symmetric Tolkowsky and GIA-reference stones have 5-7).  Each
    ring profile is low-passed to its harmonics up to 3 x ``fold`` (:func:`count_dark_lobes`), so
    that pixel-wide features do not change the count with the image size."""
    if fold < 1 or not 0.0 < min_agreement <= 1.0:
        raise InputError(
            "needs fold >= 1 and 0 < min_agreement <= 1", field="fold", value=(fold, min_agreement)
        )
    a = np.asarray(image, dtype=np.float64)
    half = a.shape[1] / 2 / 1.08  # the girdle radius in pixels (face_up_scene's 8 % margin)
    rings = HEART_RINGS if face_down else ARROW_RINGS
    # harmonics up to 3 x fold: a pattern of fold or 2 fold lobes keeps its shape, features
    # narrower than ~1/6 of the period (facet edges, pixel jitter) do not count
    per = tuple(count_dark_lobes(ring_profile(a, r * half), max_harmonic=3 * fold) for r in rings)
    vals, n = np.unique(per, return_counts=True)
    mode = int(vals[np.argmax(n)])
    agree = float(n.max() / len(per))
    if mode == fold and agree >= min_agreement:
        return LobeCount(fold, per, mode, agree, "intact")
    n_fold = sum(c == fold for c in per)
    others = sorted(c for c in per if c != fold)
    why = f"broken: {fold} lobes on {n_fold} of {len(per)} rings (others {others})"
    return LobeCount(None, per, mode, agree, why)


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
