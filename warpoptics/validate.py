"""The one validation toolkit for user input: numbers with ranges, integers, choices, booleans,
vectors and unknown keys, each raising :class:`~warpoptics.errors.InputError` with the file, the
field, the value and what is allowed.

It sits beside :mod:`warpoptics.errors` at the bottom of the package (it imports nothing else of
warpoptics), so that the scene schema (TOML tables), the stages' frozen configs (their
``__post_init__``), the bench, the sweep specs and the material specs all validate with the same
rules and give the same one-line message whether a value came from a file or from Python
(``file=None`` then).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable

import numpy as np

from .errors import InputError

__all__ = [
    "suggest",
    "check_keys",
    "number",
    "integer",
    "choice",
    "boolean",
    "vec3",
    "unit_vec3",
    "crystal_frame",
    "pair",
    "rgb",
    "finite_array",
    "flag",
]


def suggest(key: str, allowed: Iterable[str]) -> str:
    """``"; did you mean 'spp'?"`` for the closest allowed key (difflib ratio >= 0.6), else ``""``."""
    close = difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def check_keys(table: dict, allowed: Iterable[str], *, file: str | None = None, prefix: str = "") -> None:
    """Refuse a key of ``table`` that is not in ``allowed`` (field ``prefix + key``, with a suggestion)."""
    allowed = set(allowed)
    for key in table:
        if key not in allowed:
            raise InputError(
                f"unknown key{suggest(key, allowed)}",
                file=file,
                field=f"{prefix}{key}",
                allowed=", ".join(sorted(allowed)),
            )


def _range_text(lo: float, hi: float, lo_open: bool) -> str:
    lo_s = f"> {lo}" if lo_open else f">= {lo}"
    return lo_s if hi == math.inf else f"{lo_s} and <= {hi}"


def number(
    v,
    *,
    file: str | None = None,
    field: str,
    lo: float = -math.inf,
    hi: float = math.inf,
    lo_open: bool = False,
    integer: bool = False,
):
    """``v`` if it is a finite number (an ``int`` when ``integer``; never a bool) in ``[lo, hi]``
    (``(lo, hi]`` when ``lo_open``), else an InputError naming ``field``."""
    ok_type = isinstance(v, int) if integer else isinstance(v, (int, float))
    if isinstance(v, bool) or not ok_type:
        kind = "an integer" if integer else "a number"
        raise InputError(f"must be {kind}", file=file, field=field, value=v)
    try:
        finite = math.isfinite(v)
    except OverflowError:  # an int beyond the float range (a JSON or TOML integer of 400 digits)
        finite = False
    if not finite:
        raise InputError("must be a finite number", file=file, field=field, value=v)
    if v < lo or v > hi or (lo_open and v == lo):
        raise InputError(
            "out of range", file=file, field=field, value=v, allowed=_range_text(lo, hi, lo_open)
        )
    return v


def integer(v, *, file: str | None = None, field: str, lo: float = -math.inf, hi: float = math.inf) -> int:
    """``v`` if it is an integer (not a bool, not 2.0) in ``[lo, hi]``."""
    return int(number(v, file=file, field=field, lo=lo, hi=hi, integer=True))


def choice(v, allowed: Iterable[str], *, file: str | None = None, field: str) -> str:
    """``v`` if it is one of the strings ``allowed`` (a near miss gets a suggestion)."""
    allowed = tuple(allowed)
    if not isinstance(v, str) or v not in allowed:
        hint = suggest(v, allowed) if isinstance(v, str) else ""
        raise InputError(f"unknown value{hint}", file=file, field=field, value=v, allowed=", ".join(allowed))
    return v


def boolean(v, *, file: str | None = None, field: str) -> bool:
    """``v`` if it is ``True`` or ``False``; ``"no"``, ``0`` or ``1`` are refused (not truth values)."""
    if not isinstance(v, bool):
        raise InputError("must be true or false", file=file, field=field, value=v)
    return v


def vec3(v, *, file: str | None = None, field: str) -> tuple[float, float, float]:
    """Three finite numbers ``[x, y, z]`` as a tuple of floats."""
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        raise InputError("must be a list of three numbers [x, y, z]", file=file, field=field, value=v)
    x, y, z = (float(number(c, file=file, field=field)) for c in v)
    return x, y, z


def unit_vec3(v, *, file: str | None = None, field: str) -> tuple[float, float, float]:
    """A :func:`vec3` that is not the zero vector (returned as given, not normalised)."""
    x = vec3(v, file=file, field=field)
    if not any(x):
        raise InputError("must not be the zero vector", file=file, field=field, value=list(x))
    return x


def crystal_frame(v, *, file: str | None = None, field: str):
    """Three orthogonal, right-handed non-zero 3-vectors ``[[X], [Y], [Z]]`` (a crystal's principal
    axes), normalised, as a (3, 3) NumPy array of rows; orthogonality within 1e-4 (a 0.006° slack
    for hand-typed decimals), then re-orthonormalised exactly."""
    import numpy as np  # the toolkit's other checks need no NumPy

    rows = v.tolist() if hasattr(v, "tolist") else v
    if not isinstance(rows, (list, tuple)) or len(rows) != 3:
        raise InputError(
            "must be three axes [[X], [Y], [Z]] (rows of 3 numbers)", file=file, field=field, value=v
        )
    a = np.array(
        [unit_vec3(list(r) if isinstance(r, (list, tuple)) else r, file=file, field=field) for r in rows]
    )
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    g = a @ a.T
    if np.max(np.abs(g - np.eye(3))) > 1e-4:
        raise InputError(
            "crystal axes must be mutually perpendicular",
            file=file,
            field=field,
            value=[[round(float(c), 6) for c in r] for r in a],
            allowed="X . Y = Y . Z = Z . X = 0",
        )
    if np.linalg.det(a) < 0:
        raise InputError("crystal axes must be right-handed", file=file, field=field, allowed="Z = X x Y")
    # exact orthonormal frame: Gram-Schmidt on X, Y; Z = X x Y
    x = a[0]
    y = a[1] - x * (x @ a[1])
    y /= np.linalg.norm(y)
    return np.array([x, y, np.cross(x, y)])


def pair(
    v,
    *,
    file: str | None = None,
    field: str,
    lo: float = 0.0,
    hi: float = math.inf,
    lo_open: bool = True,
    integer: bool = False,
    what: str = "[width, height] in mm",
) -> tuple:
    """Two numbers ``[a, b]`` (sizes > 0 by default), each in range."""
    if not isinstance(v, (list, tuple)) or len(v) != 2:
        raise InputError(f"must be a list of two numbers {what}", file=file, field=field, value=v)
    conv = int if integer else float
    return tuple(
        conv(number(c, file=file, field=field, lo=lo, hi=hi, lo_open=lo_open, integer=integer)) for c in v
    )


def rgb(v, *, file: str | None = None, field: str, hi: float = math.inf) -> tuple[float, float, float]:
    """Linear sRGB ``[r, g, b]``, each component in ``[0, hi]``."""
    x = vec3(v, file=file, field=field)
    if min(x) < 0 or max(x) > hi:
        raise InputError(
            "out of range",
            file=file,
            field=field,
            value=list(x),
            allowed=f"linear sRGB components >= 0 and <= {hi}" if hi != math.inf else ">= 0",
        )
    return x


def finite_array(v, *, file: str | None = None, field: str) -> np.ndarray:
    """``v`` as a numeric NumPy array (real or complex, any shape) whose every element is finite;
    else an InputError naming ``field`` and the first NaN/Inf element (one line whatever the
    shape: the array itself is not printed).  The check of the element-wise NumPy wrappers."""
    try:
        a = np.asarray(v)
        if a.dtype.kind not in "biufc":
            a = a.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError("must be numeric", file=file, field=field, value=type(v).__name__) from None
    if a.dtype.kind in "fc":
        bad = ~np.isfinite(a)
        if np.any(bad):
            first = a[bad].flat[0]
            raise InputError(
                "must be finite", file=file, field=field, value=first.item(), allowed="finite numbers"
            )
    return a


def flag(
    kind: type = float,
    *,
    lo: float = -math.inf,
    hi: float = math.inf,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
):
    """An argparse ``type=`` for a command-line number: the text parsed as ``kind`` (int or
    float), finite and in ``[lo, hi]`` (open at ``lo`` when ``lo_open``, at ``hi`` when
    ``hi_open``), else an
    ``argparse.ArgumentTypeError`` with the value and the range, so that ``argparse`` refuses
    the flag on one line (exit status 2) before the command reads a file or renders anything.
    Every subcommand's numeric flags use it (the one place where a flag's range is checked)."""
    import argparse

    rng = _range_text(lo, hi, lo_open)
    if hi_open:
        rng = rng.replace(f"<= {hi}", f"< {hi}")
    rng += f" {unit}" if unit else ""
    name = "an integer" if kind is int else "a number"

    def parse(text: str):
        shown = text if len(text) <= 40 else text[:37] + "..."
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{shown!r} is not {name} (allowed: {rng})") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{shown!r} must be a finite number (allowed: {rng})")
        if v < lo or v > hi or (lo_open and v == lo) or (hi_open and v == hi):
            raise argparse.ArgumentTypeError(f"{shown} is out of range (allowed: {rng})")
        return v

    parse.__name__ = kind.__name__  # argparse names the type in its messages
    return parse


def toml_file(path, *, what: str = "scene") -> dict:
    """The table of a TOML file, or a one-line error naming the file: ``{what} file not found``,
    not UTF-8 text (with the byte), or not valid TOML (with the parser's line and column)."""
    import tomllib
    from pathlib import Path

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{what} file not found", file=str(p))
    try:
        return tomllib.loads(p.read_text(encoding="utf-8"))
    except UnicodeDecodeError as exc:
        msg = f"not a UTF-8 text file (byte {exc.start}); TOML files are UTF-8"
        raise InputError(msg, file=str(p)) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML ({exc})", file=str(p)) from None
