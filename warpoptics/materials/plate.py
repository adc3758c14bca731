"""Transmittance of a polished plate of a material (the colour of a stone of a given path length).

:func:`plate_transmittance` is the one place of this law; ``metrics.plate_transmittance`` (the
``colorchange`` command) and ``materials.fit`` (the colour fit) call it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["plate_transmittance"]


def plate_transmittance(material, thickness_mm: float, wavelength_nm) -> np.ndarray:
    """Transmittance of a polished plate in air at normal incidence: (1 - R)^2 exp(-alpha d)
    with R = |rs|^2 of ``optics.fresnel`` at each face (no multiple reflections).  A
    birefringent plate (optic axis in the plate, unpolarized light) is the mean over its
    waves (the trailing axis of ``material.n`` / ``material.alpha``).  ``material``: a library
    name, an inline table or a :class:`~warpoptics.materials.Material`."""
    from .. import validate as val
    from ..optics.fresnel import fresnel
    from .spec import material_from_spec

    mat: Any = material_from_spec(material)  # Isotropic | Uniaxial (| Biaxial): all have n, alpha
    d = float(val.number(thickness_mm, field="thickness", lo=0.0, hi=1.0e4))
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    n = np.asarray(mat.n(wl), dtype=np.float64)
    alpha = np.asarray(mat.alpha(wl), dtype=np.float64)
    rs, _rp, _ts, _tp = fresnel(np.ones_like(n), 1.0, n)
    t = (1.0 - np.abs(rs) ** 2) ** 2 * np.exp(-alpha * d)
    return t.mean(axis=-1) if t.ndim > wl.ndim else t
