"""Materials from scene files: a library name, or an inline table built on one.

```toml
material = "sapphire"
material = { base = "spinel", absorption_rgb = [0.9, 0.6, 0.05], kramers_kronig = true }
material = { base = "diamond", bands = [{ center_nm = 560, width_nm = 25, peak_alpha_per_mm = 2.0 }] }
material = { cauchy = [1.5, 0.0042] }    # n = A + B / lambda^2 (lambda in um); [2.0] is non-dispersive
material = { base = "diamond", fluorescence = { centre = "N3", quantum_yield = 0.29, strength = 2.0 } }
material = { base = "diamond_n3", fluorescence = { quantum_yield = 0.1 } }   # the entry's own centre
material = { host = "corundum", chromophores = { "Cr3+" = 0.5 } }   # a host crystal and its chromophores
material = { base = "ruby", chromophores = { Cr = 0.2 } }           # a variety, Cr3+ changed
```

Keys of an inline table: ``base`` (library name), ``cauchy`` (coefficients A, B, ... of a
Cauchy formula, lambda in micrometres) or ``host`` (a host crystal of
``materials.chromophores``), one of them required; ``chromophores`` (a table chromophore =
concentration, in each band set's unit: with ``host``, the crystal's chromophores; with a
variety as ``base``, those concentrations replace the variety's; "Cr" stands for "Cr3+" where
the host has one Cr band set); ``bands`` (Gaussian/Lorentzian
absorption bands, alpha in 1/mm base e); ``absorption_rgb`` (an eq. 9 RGB absorbance triplet in
1/mm, inverted onto a smooth spectrum, Guy & Soler 2004); ``kramers_kronig`` (add the anomalous
dispersion of the absorption, Weidlich & Wilkie 2009); ``optic_axis`` (unit vector, uniaxial);
``fluorescence`` (a luminescent centre, ``materials.fluorescence``: a centre name, or a table with
``centre`` (default: the base's own, e.g. ``diamond_n3``'s N3), ``quantum_yield`` (0..1; a plain
scene value, so ``object.0.material.fluorescence.quantum_yield`` is a sweep axis), ``strength``
(x the centre's concentration, its alpha_x) and ``add_absorption`` (default true: alpha_x is
added to the material's absorption; false when the base already holds the centre's bands, as
the library's ruby holds the Cr3+ bands)).
"""

from __future__ import annotations

import difflib
from typing import Any

import numpy as np

from .. import validate as val
from ..errors import InputError
from .absorption import AbsorptionSpectrum, Band, spectrum_from_rgb, with_absorption
from .datasets.fluorescence import CENTRES
from .dispersion import Cauchy, Material, Uniaxial
from .kramers_kronig import anomalous
from .library import chromophore_material, get, variety_chromophores

__all__ = ["material_from_spec"]

_KEYS = {
    "base",
    "cauchy",
    "host",
    "chromophores",
    "bands",
    "absorption_rgb",
    "kramers_kronig",
    "optic_axis",
    "fluorescence",
}
_FLUORESCENCE_KEYS = {"centre", "quantum_yield", "strength", "add_absorption"}
_FINEST_STEP_NM = 0.1
_MAX_RGB_ABSORBANCE = 1.0e6  # 1/mm: an absorption depth of a nanometre
_BAND_KEYS = {"center_nm", "width_nm", "peak_alpha_per_mm", "shape"}


def material_from_spec(spec: Any) -> Material:
    """A :class:`Material` from a scene's ``material`` value (see the module docstring)."""
    if isinstance(spec, Material):
        return spec
    if isinstance(spec, str):
        return get(spec)
    if not isinstance(spec, dict):
        raise InputError("must be a material name or an inline table", field="material", value=spec)
    for k in spec:
        if k not in _KEYS:
            close = difflib.get_close_matches(k, list(_KEYS), n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise InputError(f"unknown key{hint}", field=k, allowed=", ".join(sorted(_KEYS)))
    if sum(k in spec for k in ("base", "cauchy", "host")) != 1:
        raise InputError(
            'an inline material needs exactly one of base = "<library name>", cauchy = [A, B, ...] '
            'or host = "<host crystal>"',
            field="base",
        )
    if "chromophores" in spec or "host" in spec:
        for k in ("bands", "absorption_rgb"):
            if k in spec:
                raise InputError("give either chromophores or bands/absorption_rgb, not both", field=k)
        mat = _chromophores(spec)
    elif "cauchy" in spec:
        c = spec["cauchy"]
        if (
            not isinstance(c, list)
            or not c
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) for v in c)
        ):
            raise InputError("must be a list of numbers [A, B, ...]", field="cauchy", value=c)
        if c[0] < 1.0:
            raise InputError("the index must be >= 1", field="cauchy", value=c)
        mat = Cauchy(*[float(v) for v in c], name="cauchy")
    else:
        mat = get(spec["base"])
    host_fl = None
    if "fluorescence" in spec and mat.fluorescence is not None:
        host_fl = mat.fluorescence
        mat = mat.fluorescence_host  # re-applied below, on top of any new absorption
    absorption = None
    if "bands" in spec:
        bands = spec["bands"]
        if not isinstance(bands, list):
            raise InputError("must be an array of band tables", field="bands", value=bands)
        parsed = []
        for i, b in enumerate(bands):
            if not isinstance(b, dict):
                raise InputError("must be a table", field=f"bands.{i}", value=b)
            for k in b:
                if k not in _BAND_KEYS:
                    raise InputError(
                        "unknown key", field=f"bands.{i}.{k}", allowed=", ".join(sorted(_BAND_KEYS))
                    )
            for k in ("center_nm", "width_nm", "peak_alpha_per_mm"):
                if k in b and (isinstance(b[k], bool) or not isinstance(b[k], (int, float))):
                    raise InputError("must be a number", field=f"bands.{i}.{k}", value=b[k])
            try:
                parsed.append(
                    Band(
                        float(b["center_nm"]),
                        float(b["width_nm"]),
                        float(b["peak_alpha_per_mm"]),
                        b.get("shape", "gaussian"),
                    )
                )
            except KeyError as exc:
                raise InputError("missing key", field=f"bands.{i}.{exc.args[0]}") from None
            except InputError as exc:
                raise InputError(
                    exc.message, field=f"bands.{i}.{exc.field}", value=exc.value, allowed=exc.allowed
                ) from None
        # the table resolves the narrowest band (4 nodes per width), down to 0.1 nm (6,001 nodes)
        narrowest = min((b.width_nm for b in parsed), default=4.0)
        if narrowest < 4 * _FINEST_STEP_NM:
            i = min(range(len(parsed)), key=lambda j: parsed[j].width_nm)
            raise InputError(
                "narrower than the absorption table resolves",
                field=f"bands.{i}.width_nm",
                value=narrowest,
                allowed=f">= {4 * _FINEST_STEP_NM:g} nm",
            )
        absorption = AbsorptionSpectrum.from_bands(
            parsed,
            wavelength_range_nm=(300.0, 900.0),
            step_nm=min(1.0, narrowest / 4),
            name="bands",
        )
    if "absorption_rgb" in spec:
        if absorption is not None:
            raise InputError("give either bands or absorption_rgb, not both", field="absorption_rgb")
        rgb = val.vec3(spec["absorption_rgb"], field="absorption_rgb")
        if max(rgb) > _MAX_RGB_ABSORBANCE:
            raise InputError(
                "too large",
                field="absorption_rgb",
                value=list(rgb),
                allowed=f"<= {_MAX_RGB_ABSORBANCE:g} 1/mm",
            )
        absorption = spectrum_from_rgb(rgb)
    kk = spec.get("kramers_kronig", False)
    if not isinstance(kk, bool):
        raise InputError("must be true or false", field="kramers_kronig", value=kk)
    if kk and absorption is None:
        raise InputError(
            "kramers_kronig needs an absorption (bands or absorption_rgb)", field="kramers_kronig"
        )
    if absorption is not None:
        # bands: their Kramers–Kronig Δn in closed form, wherever they lie (UV/IR bands give the
        # visible index its tail); a table (absorption_rgb): the numerical integral of the table
        mat = (
            anomalous(mat, absorption, bands=parsed if "bands" in spec else None)
            if kk
            else with_absorption(mat, absorption)
        )
    if "optic_axis" in spec:
        ax = np.asarray(val.vec3(spec["optic_axis"], field="optic_axis"), dtype=float)
        if np.linalg.norm(ax) == 0:
            raise InputError(
                "must be a non-zero vector [x, y, z]", field="optic_axis", value=spec["optic_axis"]
            )
        if not isinstance(mat, Uniaxial):
            raise InputError(
                "an optic axis needs a uniaxial base material", field="optic_axis", value=spec["base"]
            )
        mat = Uniaxial(
            mat.ordinary,
            mat.extraordinary,
            optic_axis=tuple(ax / np.linalg.norm(ax)),
            name=mat.name,
            source=mat.source,
        )
    if "fluorescence" in spec:
        mat = _fluorescence(spec["fluorescence"], mat, host_fl)
    return mat


def _chromophores(spec: dict) -> Material:
    """``host = "corundum", chromophores = {...}`` (a host crystal and its chromophores), or
    ``base = "ruby", chromophores = {...}`` (a library variety with some concentrations
    replaced)."""
    from .chromophores import normalize_concentrations

    conc = spec.get("chromophores", {})
    if not isinstance(conc, dict):
        raise InputError("must be a table of chromophore = concentration", field="chromophores", value=conc)
    if "host" in spec:
        host = spec["host"]
        return chromophore_material(host, normalize_concentrations(host, conc))
    found = variety_chromophores(spec["base"])
    if found is None:
        get(spec["base"])  # an unknown name: its own error
        raise InputError(
            'has no chromophores to change; name a variety (e.g. "ruby") or give host = "<crystal>"',
            field="base",
            value=spec["base"],
        )
    host, base_conc, index = found
    merged = {**base_conc, **normalize_concentrations(host, conc)}
    return chromophore_material(host, merged, name=get(spec["base"]).name, index=index)


def _fluorescence(value: Any, mat: Material, own) -> Material:
    """Apply a ``fluorescence`` value (module docstring) to ``mat``."""
    from .. import validate as val
    from .fluorescence import centre, with_fluorescence, with_own_excitation

    if isinstance(value, str):
        value = {"centre": value}
    if not isinstance(value, dict):
        raise InputError("must be a centre name or a table", field="fluorescence", value=value)
    val.check_keys(value, _FLUORESCENCE_KEYS, prefix="fluorescence.")
    strength = float(val.number(value.get("strength", 1.0), field="fluorescence.strength", lo=0.0, hi=1.0e6))
    add = val.boolean(value.get("add_absorption", True), field="fluorescence.add_absorption")
    q = value.get("quantum_yield")
    if q is not None:
        q = float(val.number(q, field="fluorescence.quantum_yield", lo=0.0, hi=1.0))
    if "centre" in value:
        fl = centre(value["centre"], quantum_yield=q, strength=strength)
    elif own is not None:
        fl = own if q is None else own.with_yield(q)
        fl = fl if strength == 1.0 else fl.scaled(strength)
    else:
        raise InputError(
            "the base material has no luminescent centre: name one",
            field="fluorescence.centre",
            allowed=", ".join(CENTRES),
        )
    if not add:
        # the base's absorption is the centre's (its bands): the centre gives the emission and
        # the yield
        return with_own_excitation(mat, fl)
    return with_fluorescence(mat, fl)
