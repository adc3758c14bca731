"""Optical activity of a crystal: the rotatory power along its optic axis and its handedness.

:func:`optical_activity` returns the :class:`OpticalActivity` of a library crystal (data in
:mod:`.datasets.optical_activity`) in one hand: ``"right"`` (dextrorotatory: the plane of
vibration turns clockwise for an observer facing the light source) or ``"left"``.  The plate
model (``optics.plate.plate_active_jones``) takes ``rho_rad_mm(lambda)``: the rotation about the
propagation direction in rad/mm, positive counter-clockwise for that observer (from x toward y
for light along +z), so that right-handed quartz has rho < 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .datasets.optical_activity import ROTATORY_DISPERSION

__all__ = ["OpticalActivity", "optical_activity", "HANDEDNESS"]

HANDEDNESS = ("right", "left")


@dataclass(frozen=True)
class OpticalActivity:
    """Drude rotatory dispersion ``terms`` ((A_i deg um^2 / mm, lambda_i^2 um^2), ...),
    ``handedness`` ("right" | "left"), ``perpendicular_ratio`` G11 / G33, ``range_nm``,
    ``source``."""

    name: str
    terms: tuple[tuple[float, float], ...]
    handedness: str
    perpendicular_ratio: float
    range_nm: tuple[float, float]
    source: str

    def __post_init__(self) -> None:
        if self.handedness not in HANDEDNESS:
            raise InputError(
                "unknown handedness", field="handedness", value=self.handedness, allowed=", ".join(HANDEDNESS)
            )

    def rotatory_power_deg_mm(self, wavelength_nm) -> np.ndarray:
        """|rho| along the optic axis, degrees per mm: sum_i A_i / (lambda^2 - lambda_i^2)."""
        lam = np.asarray(wavelength_nm, dtype=np.float64)
        if not np.all(np.isfinite(lam)) or np.any(lam <= 0):
            raise InputError("must be finite and > 0", field="wavelength_nm", allowed="> 0")
        lo, hi = self.range_nm
        l2 = (np.clip(lam, lo, hi) * 1e-3) ** 2
        return sum(a / (l2 - b) for a, b in self.terms)

    def rho_rad_mm(self, wavelength_nm) -> np.ndarray:
        """Signed rotatory power along the axis, rad/mm, positive counter-clockwise for an
        observer facing the light source (right-handed: negative)."""
        sign = -1.0 if self.handedness == "right" else 1.0
        return sign * np.radians(self.rotatory_power_deg_mm(wavelength_nm))


def optical_activity(name: str = "quartz", handedness: str = "right") -> OpticalActivity:
    """The optical activity of library crystal ``name`` in ``handedness``."""
    if name not in ROTATORY_DISPERSION:
        raise InputError(
            "no optical-activity data", field="material", value=name, allowed=", ".join(ROTATORY_DISPERSION)
        )
    e = ROTATORY_DISPERSION[name]
    ratio = float(e["perpendicular_ratio"])
    if not math.isfinite(ratio):
        raise InputError("must be finite", field="perpendicular_ratio", value=ratio)
    return OpticalActivity(
        name=name,
        terms=tuple(tuple(t) for t in e["terms"]),
        handedness=handedness,
        perpendicular_ratio=ratio,
        range_nm=tuple(e["range_nm"]),
        source=e["source"],
    )
