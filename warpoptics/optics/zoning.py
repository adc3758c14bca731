"""Colour zoning: the optical depth of a straight segment through zones of different absorption.

A zoned stone keeps its host's refractive indices (and birefringence) everywhere; only its
absorption changes from zone to zone.  The zones are nested regions bounded by surfaces of one
family, in the stone's own (object) frame:

- **planes** (:data:`ZONE_PLANES`): the planes ``u . (x - c) = b_j`` with unit normal ``u``
  (bands parallel to a crystal face, as the hexagonal growth banding of sapphire; one plane: a
  stone in two halves, as ametrine's amethyst and citrine sectors).  Zone 0 is
  ``u . (x - c) < b_0``, zone i is ``b_{i-1} <= u . (x - c) < b_i``, the last zone lies beyond
  the last plane.
- **coaxial cylinders** (:data:`ZONE_CYLINDERS`): radii ``r_j`` about the line through ``c``
  along unit ``u`` (core and rim, as watermelon tourmaline's pink core in a green rim).  Zone 0
  is the core ``rho < r_0``, the last zone the rim ``rho >= r_{K-2}``.

Each boundary j splits a segment into an inside (the lower zones) and an outside.  For
``x(s) = o + d s``, ``s`` in ``[0, t]``, the inside of a plane is a half-line of ``s`` (one
crossing, ``s* = (b_j - u.(o - c)) / u.d``) and the inside of a cylinder an interval between the
two roots of the quadratic ``|p + q s|^2 = r_j^2`` (``p``, ``q``: the parts of ``o - c`` and
``d`` perpendicular to ``u``).  Clipped to ``[0, t]`` that gives the length ``F_j`` of the
segment inside boundary j; the boundaries are nested (``F_0 <= F_1 <= ...``), so the length in
zone i is ``L_i = F_i - F_{i-1}`` (``F_{-1} = 0``, ``F_{K-1} = t``) and the optical depth,
absorption being constant inside a zone, is exactly

    tau = sum_i kappa_i L_i,        transmitted fraction exp(-tau)

(Bouguer–Lambert, ``optics.absorption``, for an absorption coefficient that is piecewise
constant along the path).  No sorting of crossings is needed, and a segment wholly inside one
zone gets ``L_i = t`` and zeros exactly, so its depth is that zone's ``kappa t`` to the bit.

The segment may be given in any affine image of the world (the object frame of a scaled,
rotated stone): lengths are measured in the segment's parameter ``s``, which an affine map
keeps, so ``o`` and ``d`` in the object frame with the world's ``t`` (and unit world ``d``) give
world millimetres.

Per wave: kappa_i is the absorption coefficient of the wave on the segment in zone i (each
zone's own o/e or X/Y/Z spectra with the host's indices, ``stages.media.zoned_kappa``).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from ..validate import finite_array

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "MAX_ZONES",
    "ZONE_NONE",
    "ZONE_PLANES",
    "ZONE_CYLINDERS",
    "ZoneVector",
    "zone_lengths",
    "zoned_optical_depth",
    "segment_optical_depth",
    "inside_length_plane",
    "inside_length_cylinder",
]

#: most zones per stone (the per-segment lengths and absorption coefficients live in registers)
MAX_ZONES = 8
#: zone families (``MaterialTable.zone_kind``): no zoning, parallel planes, coaxial cylinders
ZONE_NONE = wp.constant(0)
ZONE_PLANES = wp.constant(1)
ZONE_CYLINDERS = wp.constant(2)

#: one value per zone (lengths in mm, absorption coefficients in 1/mm)
ZoneVector = wp.types.vector(length=MAX_ZONES, dtype=wp.float32)


@wp.func
def inside_length_plane(s0: float, ds: float, b: float, t: float):
    """Length of ``s`` in ``[0, t]`` with ``s0 + ds s < b`` (the segment's part below the plane
    at offset ``b``; ``s0``, ``ds``: the offset of its start and its rate along the normal)."""
    if ds == 0.0:
        if s0 < b:
            return t
        return 0.0
    s_cross = wp.clamp((b - s0) / ds, 0.0, t)
    if ds > 0.0:
        return s_cross
    return t - s_cross


@wp.func
def inside_length_cylinder(p: wp.vec3f, q: wp.vec3f, r: float, t: float):
    """Length of ``s`` in ``[0, t]`` with ``|p + q s| < r``: ``p``, ``q`` the parts of the
    segment's start (relative to a point of the axis) and of its direction perpendicular to the
    axis.  The roots of ``(q.q) s^2 + 2 (p.q) s + p.p - r^2 = 0`` in the cancellation-free form
    (Press et al., Numerical Recipes §5.6)."""
    a = wp.dot(q, q)
    c = wp.dot(p, p) - r * r
    if a <= 0.0:
        if c < 0.0:
            return t  # along the axis, inside
        return 0.0
    b = wp.dot(p, q)
    disc = b * b - a * c
    if disc <= 0.0:
        return 0.0
    h = -(b + wp.sign(b) * wp.sqrt(disc))
    if b == 0.0:
        h = -wp.sqrt(disc)
    s1 = h / a
    s2 = c / h
    lo = wp.max(wp.min(s1, s2), 0.0)
    hi = wp.min(wp.max(s1, s2), t)
    return wp.max(hi - lo, 0.0)


@wp.func
def zone_lengths(
    kind: int,
    axis: wp.vec3f,
    centre: wp.vec3f,
    bounds: wp.array(dtype=wp.float32),
    start: int,
    count: int,
    o: wp.vec3f,
    d: wp.vec3f,
    t: float,
):
    """Length of the segment ``o + d s``, ``s`` in ``[0, t]``, in each of ``count`` zones (module
    docstring): ``kind`` :data:`ZONE_PLANES` (normal ``axis``, offsets) or :data:`ZONE_CYLINDERS`
    (axis ``axis``, radii), through point ``centre``; the ``count - 1`` increasing offsets or
    radii are ``bounds[start : start + count - 1]``.  Lengths are in units of ``s`` (mm for a
    unit world direction); entries from ``count`` on are zero."""
    lengths = ZoneVector()
    prev = float(0.0)
    p = o - centre
    # the perpendicular parts (cylinders) and the offset and rate along the normal (planes)
    s0 = wp.dot(p, axis)
    ds = wp.dot(d, axis)
    p_perp = p - axis * s0
    q_perp = d - axis * ds
    for j in range(count - 1):
        f = float(0.0)
        if kind == ZONE_CYLINDERS:
            f = inside_length_cylinder(p_perp, q_perp, bounds[start + j], t)
        else:
            f = inside_length_plane(s0, ds, bounds[start + j], t)
        f = wp.max(f, prev)  # nested: rounding may not make an outer boundary hold less
        lengths[j] = f - prev
        prev = f
    lengths[count - 1] = t - prev
    return lengths


@wp.func
def zoned_optical_depth(lengths: ZoneVector, kappa: ZoneVector, count: int):
    """Optical depth sum_i kappa_i L_i (dimensionless; L in mm, kappa in 1/mm) of a segment with
    the lengths :func:`zone_lengths` in zones of absorption coefficients ``kappa``; its
    transmitted fraction is exp(-depth).  Zones it does not cross add exact zeros."""
    depth = float(0.0)
    for i in range(count):
        if lengths[i] > 0.0:
            depth += kappa[i] * lengths[i]
    return depth


# ----------------------------------------------------------------------------------------------
# NumPy wrapper
# ----------------------------------------------------------------------------------------------

_KINDS = {"planes": 1, "cylinders": 2}


@wp.kernel
def _zoned_depth_kernel(
    offset: int,
    o: wp.array(dtype=wp.vec3f),
    d: wp.array(dtype=wp.vec3f),
    t: wp.array(dtype=wp.float32),
    kind: int,
    axis: wp.vec3f,
    centre: wp.vec3f,
    bounds: wp.array(dtype=wp.float32),
    kappa: wp.array(dtype=wp.float32),
    count: int,
    depth: wp.array(dtype=wp.float32),
    lengths: wp.array(dtype=ZoneVector),
):
    i = wp.tid() + offset
    ln = zone_lengths(kind, axis, centre, bounds, 0, count, o[i], d[i], t[i])
    k = ZoneVector()
    for j in range(count):
        k[j] = kappa[j]
    depth[i] = zoned_optical_depth(ln, k, count)
    lengths[i] = ln


@device_function(zoned_optical_depth)
def segment_optical_depth(
    origin,
    direction,
    length,
    *,
    kind: str,
    axis,
    bounds,
    kappa,
    centre=(0.0, 0.0, 0.0),
    device=None,
) -> tuple[np.ndarray, np.ndarray]:
    """Optical depth of segments ``origin + direction s``, ``s`` in ``[0, length]`` (arrays
    (..., 3), (..., 3), (...), mm) through zones of absorption ``kappa`` (K values, 1/mm):
    ``kind`` "planes" (normal ``axis``, K - 1 increasing ``bounds`` = offsets along it from
    ``centre``) or "cylinders" (axis ``axis`` through ``centre``, K - 1 increasing radii).
    Returns (depth (...), lengths in each zone (..., K)); exp(-depth) is the transmitted fraction.
    """
    if kind not in _KINDS:
        raise InputError("unknown zone family", field="kind", value=kind, allowed="planes, cylinders")
    origin = finite_array(origin, field="origin")
    direction = finite_array(direction, field="direction")
    length = finite_array(length, field="length")
    if np.any(length < 0.0):
        raise InputError("must be >= 0", field="length", value=float(length[length < 0.0].flat[0]))
    k = finite_array(kappa, field="kappa").astype(np.float64).reshape(-1)
    b = finite_array(bounds, field="bounds").astype(np.float64).reshape(-1)
    if not 1 <= k.size <= MAX_ZONES:
        raise InputError("wrong number of zones", field="kappa", value=k.size, allowed=f"1 to {MAX_ZONES}")
    if b.size != k.size - 1:
        raise InputError(
            "one boundary fewer than zones", field="bounds", value=b.size, allowed=str(k.size - 1)
        )
    if b.size > 1 and np.any(np.diff(b) <= 0.0):
        raise InputError("must increase", field="bounds", value=b.tolist())
    ax = finite_array(axis, field="axis").astype(np.float64).reshape(3)
    if not np.linalg.norm(ax) > 0.0:
        raise InputError("must be a non-zero vector", field="axis", value=ax.tolist())
    ax = ax / np.linalg.norm(ax)
    dev_bounds = wp.array(np.append(b, 0.0).astype(np.float32), dtype=wp.float32, device=device)
    dev_kappa = wp.array(k.astype(np.float32), dtype=wp.float32, device=device)
    depth, lengths = elementwise(
        _zoned_depth_kernel,
        [(origin, wp.vec3f), (direction, wp.vec3f), (length, wp.float32)],
        [wp.float32, ZoneVector],
        extra=(
            _KINDS[kind],
            wp.vec3f(*ax.astype(np.float32)),
            wp.vec3f(*finite_array(centre, field="centre").astype(np.float32).reshape(3)),
            dev_bounds,
            dev_kappa,
            int(k.size),
        ),
        device=device,
    )
    return depth.astype(np.float64), lengths[..., : k.size].astype(np.float64)
