"""Design tools of cut grading: critical angles per facet tier, retargeting a GemCAD design to
another index, and perturbed brilliants for symmetry studies.

- :func:`critical_angle` — θc = asin(n_out / n) (Snell; total internal reflection beyond it).
- :func:`tier_report` — per tier of a :class:`~warpoptics.geometry.gemcad.Design`: its angle, and
  for pavilion tiers whether a face-up ray (entering the table along the axis) meets it below the
  critical angle and so leaves the stone (the tier *windows*).  A vertical ray meets a facet cut
  at angle θ to the girdle plane at incidence θ, so a pavilion tier windows when |θ| < θc
  (faceters' rule; e.g. G. Vargas & M. Vargas, *Faceting for Amateurs*, 1977, ch. on critical
  angle).  It is a first-bounce check: light reaching the tier after other reflections is the
  renderer's job (:mod:`warpoptics.grading.scopes`).
- :func:`retarget` — the design for another index: every pavilion tier keeps its margin over
  the critical angle (θ' = θ + θc(n') − θc(n), same sign), crown tiers are kept, the header's
  index is set; tiers still below θc' are reported.  A heuristic of the faceting literature (the
  pavilion carries the TIR condition, the crown mostly the dispersion and the look); the result
  should be checked with a render.
- :func:`brilliant_with_misaligned_main` — a round brilliant with one pavilion main re-cut at a
  different angle through the same culet point (the Hearts & Arrows symmetry test).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import InputError
from ..geometry.cuts import convex_from_planes, round_brilliant

__all__ = ["critical_angle", "tier_report", "retarget", "brilliant_with_misaligned_main"]


def critical_angle(n: float, n_out: float = 1.0) -> float:
    """Critical angle (degrees) from a medium of index ``n`` into ``n_out``: asin(n_out / n)."""
    if not (n > n_out > 0):
        raise InputError("needs n > n_out > 0", field="index", value=(n, n_out))
    return math.degrees(math.asin(n_out / n))


def tier_report(design, n: float | None = None) -> list[dict]:
    """One row per tier: ``name``, ``angle`` (degrees, negative pavilion), ``part`` (crown,
    pavilion, table, culet, girdle), ``margin`` (|angle| − θc for pavilion tiers, degrees) and
    ``windows`` (True: a face-up ray leaves through it; see the module docstring); ``n``
    defaults to the design's index."""
    idx = float(design.index if n is None else n)
    tc = critical_angle(idx)
    rows = []
    for i, t in enumerate(design.tiers):
        ang = float(t.angle)
        if t.is_table:
            part = "table"
        elif t.is_culet:
            part = "culet"
        elif abs(abs(ang) - 90.0) < 1e-9:
            part = "girdle"
        else:
            part = "pavilion" if ang < 0 else "crown"
        margin = abs(ang) - tc if part == "pavilion" else None
        name = t.instruction or (next(iter(t.names.values())) if t.names else f"tier {i}")
        rows.append(
            {
                "tier": i,
                "name": name,
                "angle": ang,
                "part": part,
                "critical_angle": tc,
                "margin": margin,
                "windows": bool(margin is not None and margin < 0),
            }
        )
    return rows


def retarget(design, n_new: float):
    """The design re-cut for index ``n_new`` (module docstring) and its :func:`tier_report`."""
    if not n_new > 1.0:
        raise InputError("must be > 1", field="index", value=n_new)
    d_tc = critical_angle(n_new) - critical_angle(float(design.index))
    tiers = []
    for row, t in zip(tier_report(design), design.tiers, strict=True):
        if row["part"] == "pavilion":
            a = -(abs(t.angle) + d_tc)
            if not -89.9 < a < -0.1:
                raise InputError("retargeting leaves no valid pavilion angle", field=row["name"], value=a)
            t = dataclasses.replace(t, angle=a)
        tiers.append(t)
    out = dataclasses.replace(design, tiers=tiers, refractive_index=float(n_new))
    return out, tier_report(out)


def brilliant_with_misaligned_main(delta_deg: float, *, main: int = 0, **kw):
    """A :func:`~warpoptics.geometry.cuts.round_brilliant` (keywords as there) whose pavilion
    main ``main`` (0-7) is cut ``delta_deg`` steeper (negative: shallower) through the same culet
    point; every other facet plane is kept.  ``delta_deg = 0`` rebuilds the exact stone."""
    if not 0 <= main < 8:
        raise InputError("must be 0-7", field="main", value=main)
    mesh = round_brilliant(**kw)
    planes = np.array(mesh.metadata["planes"], dtype=np.float64)
    names = list(mesh.metadata["facet_names"])
    k = names.index(f"pavilion main {main}")
    n = planes[k, :3]
    culet = mesh.vertices[np.argmin(mesh.vertices[:, 2])]
    tilt = math.acos(max(-1.0, min(1.0, -n[2])))  # the facet's angle to the girdle plane
    phi = math.atan2(n[1], n[0])
    t2 = tilt + math.radians(delta_deg)
    n2 = np.array([math.sin(t2) * math.cos(phi), math.sin(t2) * math.sin(phi), -math.cos(t2)])
    planes[k, :3] = n2
    planes[k, 3] = float(n2 @ culet)
    out = convex_from_planes(planes[:, :3], planes[:, 3], names, proportions=mesh.metadata["proportions"])
    out.metadata["symmetry"] = (8, True) if delta_deg == 0 else (1, False)
    return out
