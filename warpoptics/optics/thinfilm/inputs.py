"""Checks of the thin-film NumPy wrappers' arguments, shared by the stack, Smits–Meyer and table
wrappers: each bad value is one :class:`~warpoptics.errors.InputError` naming the argument."""

from __future__ import annotations

import numpy as np

from ...errors import InputError

__all__ = ["complex_pairs", "cos_angle", "positive"]


def _first(a: np.ndarray, bad: np.ndarray):
    """The first element of ``a`` where ``bad``, as a Python number (for one-line messages)."""
    return a[bad].flat[0].item()


def complex_pairs(value, name: str) -> np.ndarray:
    """A complex array-like as float64 (..., 2) (re, im); checks finiteness and k >= 0."""
    a = np.asarray(value)
    if a.dtype == object:
        raise InputError(f"{name} must be numeric", field=name, value=value)
    a = a.astype(np.complex128)
    # each message shows the first offending element, not the array (one line at any size)
    if not np.all(np.isfinite(a)):
        raise InputError(
            f"{name} must be finite", field=name, value=_first(a, ~np.isfinite(a)), allowed="finite n + ik"
        )
    if np.any(a.imag < 0.0):
        raise InputError(
            f"{name} has a negative extinction coefficient (gain)",
            field=name,
            value=_first(a, a.imag < 0.0),
            allowed="n + ik with k >= 0 (absorbing convention, exp(-i omega t))",
        )
    if np.any(a.real <= 0.0):
        raise InputError(
            f"{name} must have a positive real part",
            field=name,
            value=_first(a, a.real <= 0.0),
            allowed="n > 0",
        )
    return np.stack([a.real, a.imag], axis=-1)


def cos_angle(angle, name: str = "angle") -> np.ndarray:
    a = np.asarray(angle, dtype=np.float64)
    bad = ~np.isfinite(a) | (a < 0.0) | (a > 90.0)
    if np.any(bad):
        raise InputError(
            f"{name} must be an angle of incidence in degrees",
            field=name,
            value=_first(a, bad),
            allowed="0 <= angle <= 90",
        )
    return np.where(a == 90.0, 0.0, np.cos(np.radians(a)))


def positive(value, name: str, allow_zero: bool = False) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    bad = ~np.isfinite(a) | ((a < 0.0) if allow_zero else (a <= 0.0))
    if np.any(bad):
        raise InputError(
            f"{name} must be finite and {'>= 0' if allow_zero else '> 0'}",
            field=name,
            value=_first(a, bad),
            allowed=">= 0" if allow_zero else "> 0",
        )
    return a
