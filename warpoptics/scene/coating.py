"""The one coating / film schema of ``[[object]]`` tables, for camera and bench scenes alike:
``surface`` ("solid", "shell", "film"), ``coating`` (layers front to substrate, each
``{ n = ..., k = ..., thickness_nm = ... }`` or ``{ material = "name", thickness_nm = ... }``),
``film_thickness`` (a thickness profile) and ``roughness`` -> :class:`~warpoptics.stages.coated.FilmConfig`.
"""

from __future__ import annotations

from .. import validate as val
from ..errors import InputError
from ..stages.coated import SURFACE_KINDS, THICKNESS_PROFILES, FilmConfig, layer_material

__all__ = ["film_config", "FILM_KEYS"]

FILM_KEYS = ("surface", "coating", "film_thickness", "roughness")
_LAYER_KEYS = {"n", "k", "material", "thickness_nm"}
_PROFILE_KEYS = {
    "uniform": {"profile"},
    "gravity": {"profile", "top_nm", "bottom_nm", "noise", "noise_scale", "seed", "octaves"},
    "oil_drop": {"profile", "max_nm", "k1", "k2", "noise_scale", "seed", "octaves"},
}
_PROFILE_DEFAULTS = {
    "gravity": {
        "top_nm": 0.0,
        "bottom_nm": 1000.0,
        "noise": 0.15,
        "noise_scale": 3.0,
        "seed": 0,
        "octaves": 5,
    },
    "oil_drop": {"max_nm": 1000.0, "k1": 3.0, "k2": 0.3, "noise_scale": 4.0, "seed": 0, "octaves": 6},
}


def film_config(table: dict, index: int, file: str | None) -> FilmConfig | None:
    """Validate the film keys (``surface``, ``coating``, ``film_thickness``, ``roughness``) of
    ``[[object]]`` number ``index``; None when it has none.  Errors name file, field and value."""
    if not any(k in table for k in FILM_KEYS):
        return None
    prefix = f"object.{index}."
    surface = val.choice(
        table.get("surface", "solid"), tuple(SURFACE_KINDS), file=file, field=prefix + "surface"
    )
    coat = table.get("coating", [])
    if isinstance(coat, dict):
        coat = [coat]
    if not isinstance(coat, list):
        raise InputError("must be an array of layer tables", file=file, field=prefix + "coating", value=coat)
    layers = []
    for j, layer in enumerate(coat):
        f = f"{prefix}coating.{j}."
        if not isinstance(layer, dict):
            raise InputError(
                "must be a table { material = ..., thickness_nm = ... }", file=file, field=f[:-1], value=layer
            )
        val.check_keys(layer, _LAYER_KEYS, file=file, prefix=f)
        if "thickness_nm" not in layer:
            raise InputError("missing key", file=file, field=f + "thickness_nm")
        d = float(val.number(layer["thickness_nm"], file=file, field=f + "thickness_nm", lo=0.0, hi=1.0e6))
        if ("n" in layer) == ("material" in layer):
            raise InputError(
                'a layer needs exactly one of n = ... or material = "name"', file=file, field=f + "material"
            )
        if "n" in layer:
            n = float(val.number(layer["n"], file=file, field=f + "n", lo=1.0e-3, hi=100.0))
            k = float(val.number(layer.get("k", 0.0), file=file, field=f + "k", lo=0.0, hi=100.0))
            layers.append((complex(n, k), d))
        else:
            if "k" in layer:
                raise InputError(
                    "k goes with n, not with material", file=file, field=f + "k", value=layer["k"]
                )
            layer_material(layer["material"], file, f + "material")  # validate now
            layers.append((layer["material"], d))
    if surface in ("shell", "film") and not layers:
        raise InputError(
            f'a surface = "{surface}" object needs a coating (its film layers)',
            file=file,
            field=prefix + "coating",
        )
    th = table.get("film_thickness", {"profile": "uniform"})
    if not isinstance(th, dict):
        raise InputError(
            "must be a table { profile = ... }", file=file, field=prefix + "film_thickness", value=th
        )
    profile = val.choice(
        th.get("profile", "uniform"),
        tuple(THICKNESS_PROFILES),
        file=file,
        field=prefix + "film_thickness.profile",
    )
    val.check_keys(th, _PROFILE_KEYS[profile], file=file, prefix=prefix + "film_thickness.")
    params = dict(_PROFILE_DEFAULTS.get(profile, {}))
    for k, v in th.items():
        if k == "profile":
            continue
        fld = prefix + "film_thickness." + k
        if k in ("seed", "octaves"):
            params[k] = val.integer(
                v, file=file, field=fld, lo=0 if k == "seed" else 1, hi=2**31 - 1 if k == "seed" else 12
            )
        else:
            params[k] = float(val.number(v, file=file, field=fld, lo=0.0, hi=1.0e6))
    if profile != "uniform" and not layers:
        raise InputError("a thickness profile needs a coating", file=file, field=prefix + "film_thickness")
    roughness = float(
        val.number(table.get("roughness", 0.0), file=file, field=prefix + "roughness", lo=0.0, hi=1.0)
    )
    if roughness > 0.0 and surface != "film":
        raise InputError(
            'roughness applies to surface = "film" only',
            file=file,
            field=prefix + "roughness",
            value=roughness,
        )
    return FilmConfig(
        surface=surface, layers=tuple(layers), profile=profile, profile_params=params, roughness=roughness
    )
