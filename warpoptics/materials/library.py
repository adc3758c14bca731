"""The gem library: ``get(name)`` -> :class:`Isotropic` | :class:`Uniaxial`.

Dispersion comes from a refractiveindex.info page where one exists (read offline with
:func:`from_refractiveindex`); otherwise a two-term Cauchy formula n = A + B/λ² (λ in µm) is fitted
exactly through a published index and dispersion.  The numbers (pages, constants, bands) and their
provenance are data, in :mod:`warpoptics.materials.datasets` (``gems``, ``guy_soler_2004``, ``dyes``);
this module composes the materials from them.  Biaxial
stones (peridot, andalusite, topaz, tanzanite, iolite, chrysoberyl, alexandrite, kyanite) are
:class:`Biaxial` with three principal indices.  The uniaxial approximation that Guy & Soler 2004
use for peridot and andalusite (§3.2: "behave visually as if they were uniaxial because two of
the three absorbance spectra are nearly identical") stays available as explicit entries,
``peridot_uniaxial``, ``andalusite_uniaxial`` (the §6.1 table's indices and absorbances) and
``topaz_uniaxial`` (n_alpha, n_gamma as n_o, n_e); their n_o / n_e are two principal indices
named per entry.  ``Biaxial.uniaxial_approximation()`` gives the same approximation of any
biaxial entry from its own indices.  The optic axis defaults to +z (object frame).

Formula pages whose range stops short of the colour range 360–830 nm are *extrapolated* to it
(their Sellmeier poles are far in the UV/IR); the ``source`` string says so.  Colour: the six gems
of Guy & Soler §6.1 (garnet, tourmaline, peridot, diamond, sapphire, andalusite) carry the eq. 9
inversion of that table's absorbances as K^o(λ), K^e(λ), and the table's triplets themselves as
``rgb3_alpha``; the named varieties (ruby, blue_sapphire, emerald, aquamarine, alexandrite,
almandine, amethyst, tanzanite, ...: :mod:`.datasets.varieties`) are a host crystal's index with
the absorption of its chromophores (:mod:`.chromophores`, :func:`chromophore_material`), and
replace older entries of the same name; the others are colourless (k = 0).

References (gemological constants)
----------------------------------
- GIA Gem Reference Guide (1995) and R. Webster, *Gems*, 5th ed. (1994), property tables:
  zircon (high) n_o 1.925, n_e 1.984, dispersion 0.039; emerald n_o 1.583, n_e 1.577, 0.014;
  topaz n_α 1.619, n_γ 1.627, 0.014; diamond 2.417, 0.044; sapphire 1.768/1.760, 0.018;
  calcite 1.658/1.486; moissanite (6H-SiC) 2.648/2.691, 0.104; cubic zirconia 2.15–2.18, 0.060.
- S. Guy, C. Soler, ACM TOG 23(3) 2004, §6.1 table (garnet, tourmaline, peridot, andalusite).
- Handbook of Mineralogy (Mineral Data Publishing 2001): forsterite, andalusite, topaz (indices,
  2V, optic sign; see :mod:`.datasets.gems`).
- The chromophore band sets cite their own sources (:mod:`.datasets.chromophores`).
"""

from __future__ import annotations

import difflib
import functools
from collections.abc import Callable

import numpy as np

from ..errors import InputError
from .absorption import AbsorptionSpectrum, Band, guy_soler_2004_spectra, with_absorption
from .chromophores import host_alpha, host_info, normalize_concentrations
from .datasets.colour_change import COLOUR_CHANGE_GARNET
from .datasets.dyes import LIBRARY_SOLUTIONS
from .datasets.gems import CR3_BANDS_SOURCE, GEMS
from .datasets.guy_soler_2004 import GUY_SOLER_2004_ALPHA_PER_MM, GUY_SOLER_2004_GEMS
from .datasets.varieties import VARIETIES
from .dispersion import VISIBLE_RANGE_NM, Biaxial, Cauchy, Isotropic, Material, Uniaxial
from .kramers_kronig import anomalous, fuchsine_absorption, rose_bengal_absorption
from .refractiveindex import from_refractiveindex

__all__ = [
    "get",
    "names",
    "cauchy_from_gem_constants",
    "ALIASES",
    "rose_bengal_solution",
    "fuchsine_solution",
    "chromophore_material",
    "variety_chromophores",
]

_FRAUNHOFER_D = 589.3
_BG = (430.8, 686.7)
_RGB = (435.8, 700.0)


def cauchy_from_gem_constants(
    n_ref: float,
    dispersion: float,
    *,
    ref_nm: float = _FRAUNHOFER_D,
    pair_nm: tuple[float, float] = _BG,
    name: str = "gem",
    source: str = "",
) -> Isotropic:
    """Cauchy n = A + B/λ² through n(ref_nm) = n_ref and n(pair[0]) − n(pair[1]) = dispersion."""
    for v, f in ((n_ref, "n_ref"), (dispersion, "dispersion")):
        if not np.isfinite(v):
            raise InputError("must be finite", field=f, value=v)
    if n_ref < 1.0:
        raise InputError("refractive index must be >= 1", field="n_ref", value=n_ref)
    if dispersion < 0:
        raise InputError("dispersion must be >= 0", field="dispersion", value=dispersion)
    s, lg = pair_nm[0] * 1e-3, pair_nm[1] * 1e-3
    B = dispersion / (1.0 / s**2 - 1.0 / lg**2)
    A = n_ref - B / (ref_nm * 1e-3) ** 2
    return Cauchy(
        A,
        B,
        wavelength_range_nm=VISIBLE_RANGE_NM,
        name=name,
        source=source
        or f"Cauchy fit: n({ref_nm:g} nm) = {n_ref}, n({pair_nm[0]:g})−n({pair_nm[1]:g}) = {dispersion}",
    )


def _page(page: str, name: str, *, extend: bool = True) -> Isotropic:
    m = from_refractiveindex(page, name=name)
    lo, hi = m.wavelength_range_nm
    if extend and m.channel.formula_kind and (lo > VISIBLE_RANGE_NM[0] or hi < VISIBLE_RANGE_NM[1]):
        new = (min(lo, VISIBLE_RANGE_NM[0]), max(hi, VISIBLE_RANGE_NM[1]))
        m = Isotropic(
            m.channel,
            wavelength_range_nm=new,
            name=name,
            source=f"{m.source}; formula extrapolated from its {lo:g}–{hi:g} nm range "
            f"to {new[0]:g}–{new[1]:g} nm",
        )
    return m


def _uniaxial(o: Isotropic, e: Isotropic, name: str, source: str, rgb3=None) -> Uniaxial:
    return Uniaxial(o, e, optic_axis=(0.0, 0.0, 1.0), name=name, source=source, rgb3_alpha=rgb3)


def _guy_soler_triplets(name: str) -> dict[str, tuple[float, ...]]:
    """The §6.1 absorbance triplets of row ``name`` in 1/mm: {"o": K^o, "e": K^e} (K^e = K^o for
    an isotropic row)."""
    row = GUY_SOLER_2004_GEMS[name]
    ko = tuple(float(v) * GUY_SOLER_2004_ALPHA_PER_MM for v in row["K_o"])
    ke = tuple(float(v) * GUY_SOLER_2004_ALPHA_PER_MM for v in (row["K_e"] or row["K_o"]))
    return {"o": ko, "e": ke}


def _guy_soler_absorption(name: str, mat: Material) -> Material:
    """Attach the §6.1 absorbances of row ``name``: spectra by eq. 9 inversion, the triplets
    for rgb3."""
    so, se = guy_soler_2004_spectra(name)
    t = _guy_soler_triplets(name)
    ko, ke = t["o"], t["e"]
    src = mat.source + "; absorbance: Guy & Soler 2004 §6.1 (eq. 9 inversion)"
    if isinstance(mat, Uniaxial):
        out = with_absorption(mat, (so, se), source=src)
        out.rgb3_alpha = (ko, ke)
    else:
        out = with_absorption(mat, so, source=src)
        out.rgb3_alpha = (ko, ko)
    return out


def _guy_soler_indices(name: str, row_name: str | None = None) -> Material:
    """Cauchy fits to the §6.1 indices of row ``row_name`` (default ``name``): n(546.1) = table
    value, n(435.8) − n(700) = 2 ± value."""
    row = GUY_SOLER_2004_GEMS[row_name or name]
    disp = 2.0 * row["half_dispersion"]
    kw = dict(ref_nm=546.1, pair_nm=_RGB)
    src = (
        f"Guy & Soler 2004 §6.1: n_o {row['n_o']}"
        + (f", n_e {row['n_e']}" if row["n_e"] else "")
        + f" ± {row['half_dispersion']} (green ± half dispersion), Cauchy fit"
    )
    o = cauchy_from_gem_constants(row["n_o"], disp, name=f"{name} (o)", source=src, **kw)
    if row["n_e"] is None:
        o.name, o.source = name, src
        return o
    e = cauchy_from_gem_constants(row["n_e"], disp, name=f"{name} (e)", source=src, **kw)
    if row["type"] == "B":
        src += " (biaxial, treated as uniaxial as in the source)"
    return _uniaxial(o, e, name, src)


def _bands(bands, name) -> AbsorptionSpectrum:
    return AbsorptionSpectrum.from_bands(
        [Band(c, w, peak) for c, w, peak in bands],
        wavelength_range_nm=(300.0, 900.0),
        name=name,
        source=CR3_BANDS_SOURCE,
    )


def _gem(name: str, entry: dict | None = None) -> Material:
    """Build library entry ``name`` from its data (:data:`~.datasets.gems.GEMS`, or ``entry`` in
    that format)."""
    entry = GEMS[name] if entry is None else entry
    row = entry.get("guy_soler_row", name)  # the §6.1 row of "guy_soler_2004" indices/absorbances
    kind, *args = entry["index"]
    if kind == "page":
        mat = _page(args[0], name)
    elif kind == "pages":
        o = _page(args[0], f"{name} (o)")
        e = _page(args[1], f"{name} (e)")
        mat = _uniaxial(o, e, name, entry["source"])
    elif kind == "constants":
        n_o, n_e, dispersion = args
        src = entry["source"]
        o = cauchy_from_gem_constants(n_o, dispersion, name=f"{name} (o)", source=src)
        e = cauchy_from_gem_constants(n_e, dispersion, name=f"{name} (e)", source=src)
        mat = _uniaxial(o, e, name, src)
    elif kind == "biaxial":
        *n3, dispersion = args
        src = entry["source"]
        ch = [
            cauchy_from_gem_constants(n, dispersion, name=f"{name} ({a})", source=src)
            for n, a in zip(n3, "abg", strict=True)
        ]
        mat = Biaxial(*ch, name=name, source=src)
    elif kind == "biaxial_pages":
        ch = [_page(pg, f"{name} ({a})") for pg, a in zip(args, "abg", strict=True)]
        mat = Biaxial(*ch, name=name, source=entry["source"])
    else:  # "guy_soler_2004"
        mat = _guy_soler_indices(name, row)
    absorption = entry.get("absorption")
    if isinstance(mat, Biaxial):
        if absorption is None:
            return mat
        if all(absorption[a] in ("o", "e") for a in "xyz"):
            # the §6.1 spectra of the Guy & Soler row, one per principal axis, and their triplets
            so, se = guy_soler_2004_spectra(row)
            spec = {"o": so, "e": se}
            t = _guy_soler_triplets(row)
            out = with_absorption(
                mat,
                tuple(spec[absorption[a]] for a in "xyz"),
                source=mat.source + "; " + absorption["source"],
            )
            out.rgb3_alpha = tuple(t[absorption[a]] for a in "xyz")
            return out
        kx, ky, kz = (_bands(absorption[a], f"{name} alpha_{a.upper()}") for a in "xyz")
        return with_absorption(mat, (kx, ky, kz), source=mat.source + "; " + absorption["source"])
    if absorption == "guy_soler_2004":
        return _guy_soler_absorption(row, mat)
    if absorption is not None:
        ko = _bands(absorption["o"], f"{name} K^o")
        ke = _bands(absorption["e"], f"{name} K^e")
        return with_absorption(mat, (ko, ke), source=mat.source + "; " + absorption["source"])
    return mat


def chromophore_material(
    host: str,
    concentrations: dict,
    *,
    name: str | None = None,
    index: tuple | None = None,
    source: str | None = None,
) -> Material:
    """The host crystal ``host`` (:mod:`.chromophores`) coloured by ``concentrations``
    ({chromophore: concentration in its band set's unit}): the colourless crystal's index (the
    host's ``index`` entry, or ``index`` in the :data:`~.datasets.gems.GEMS` format) with alpha
    per polarization from :func:`~.chromophores.host_alpha` (o/e uniaxial, X/Y/Z biaxial).  The
    result carries ``chromophore_host`` and ``chromophore_concentrations``."""
    info = host_info(host)
    conc = normalize_concentrations(host, concentrations)
    label = name or host
    index = index or info["index"]
    if index[0] == "isotropic_constants":  # (kind, n_D, dispersion): a cubic crystal's gem constants
        base: Material = cauchy_from_gem_constants(
            index[1], index[2], name=label, source=source or info["source"]
        )
    else:
        base = _gem(label, {"index": index, "source": source or info["source"]})
    spectra = host_alpha(host, conc)
    src = f"{base.source}; {spectra[0].source}"
    absorption = spectra[0] if len(spectra) == 1 else spectra
    out = with_absorption(base, absorption, name=label, source=src)
    out.name, out.source = label, src
    out.chromophore_host = host_info(host)["name"]
    out.chromophore_concentrations = conc
    return out


def _variety(name: str) -> Material:
    """Library entry ``name`` of :data:`~.datasets.varieties.VARIETIES`."""
    v = VARIETIES[name]
    mat = chromophore_material(v["host"], v["concentrations"], name=name, index=v.get("index"))
    if "optic_axis" in v:
        mat = Uniaxial(
            mat.ordinary, mat.extraordinary, optic_axis=v["optic_axis"], name=name, source=mat.source
        )
        mat.chromophore_host = v["host"]
        mat.chromophore_concentrations = normalize_concentrations(v["host"], v["concentrations"])
    mat.source = f"{mat.source}; concentrations: {v['source']}"
    if "fluorescence" in v:  # the centre's absorption is the variety's own bands
        from .fluorescence import centre, with_own_excitation

        mat = with_own_excitation(mat, centre(v["fluorescence"]))
    return mat


def variety_chromophores(name: str) -> tuple[str, dict[str, float], tuple | None] | None:
    """(host, concentrations, index entry or None) of the library variety ``name`` (any accepted
    spelling), or None when ``name`` is not a chromophore variety."""
    key = _key(name) if isinstance(name, str) else None
    if key not in VARIETIES:
        return None
    v = VARIETIES[key]
    return v["host"], normalize_concentrations(v["host"], v["concentrations"]), v.get("index")


def rose_bengal_solution(percent: float = 10.0, *, device=None) -> Isotropic:
    """Rose bengal in water (Weidlich & Wilkie §4.2): water + Kramers–Kronig of the dye's k."""
    return anomalous(
        get("water"),
        rose_bengal_absorption(percent),
        name=f"rose_bengal_{percent:g}",
        source=f"water (Daimon 20 °C) + rose bengal {percent:g} % (Gaussian bands) + Kramers–Kronig",
        device=device,
    )


def fuchsine_solution(percent: float = 1.0, *, device=None) -> Isotropic:
    """Fuchsine in water (Weidlich & Wilkie fig. 1): water + Kramers–Kronig of the dye's k."""
    return anomalous(
        get("water"),
        fuchsine_absorption(percent),
        name=f"fuchsine_{percent:g}",
        source=f"water (Daimon 20 °C) + fuchsine {percent:g} % (Gaussian bands) + Kramers–Kronig",
        device=device,
    )


#: fluorescent library entries: name -> (host library name, centre of datasets.fluorescence); the
#: chromophore varieties name their centre in their own entry (red_spinel: "Cr3+ spinel")
FLUORESCENT = {
    "diamond_n3": ("diamond", "N3"),
    "uranium_glass": ("bk7", "uranyl glass"),
}


def _fluorescent(name: str) -> Material:
    """A host with a luminescent centre (materials.fluorescence; uranium glass: N-BK7 stands in
    for the soda-lime host glass, n_D 1.517 vs 1.50-1.52)."""
    from .fluorescence import centre, with_fluorescence

    host, which = FLUORESCENT[name]
    return with_fluorescence(get(host), centre(which), name=name)


def _colour_change_garnet() -> Material:
    """The colour-change garnet of :mod:`.datasets.colour_change` (isotropic)."""
    d = COLOUR_CHANGE_GARNET
    mat = cauchy_from_gem_constants(
        d["n_d"], d["dispersion"], name="colour_change_garnet", source=d["source"]
    )
    fwhm_to_sigma = 1.0 / (2.0 * np.sqrt(2.0 * np.log(2.0)))
    absorption = AbsorptionSpectrum.from_bands(
        [Band(c, w * fwhm_to_sigma, a) for c, w, a in d["bands"]],
        wavelength_range_nm=(300.0, 900.0),
        name="colour_change_garnet",
        source=d["source"],
    )
    return with_absorption(mat, absorption, name="colour_change_garnet", source=d["source"])


def _dye(kind: str, percent: float) -> Callable[[], Material]:
    def build() -> Material:
        return rose_bengal_solution(percent) if kind == "rose_bengal" else fuchsine_solution(percent)

    return build


_BUILDERS: dict[str, Callable[[], Material]] = {
    **{name: functools.partial(_gem, name) for name in GEMS},
    **{name: _dye(kind, percent) for name, (kind, percent) in LIBRARY_SOLUTIONS.items()},
    **{name: functools.partial(_fluorescent, name) for name in FLUORESCENT},
    "colour_change_garnet": _colour_change_garnet,
    # chromophore varieties last: they replace older entries of the same name
    **{name: functools.partial(_variety, name) for name in VARIETIES},
}

#: other accepted spellings
ALIASES = {
    "beryl": "emerald",
    "corundum": "sapphire",
    "cz": "cubic_zirconia",
    "n-bk7": "bk7",
    "silica": "fused_silica",
    "olivine": "peridot",
    "h2o": "water",
    "color_change_garnet": "colour_change_garnet",
}

_cache: dict[str, Material] = {}


def names() -> list[str]:
    """All library names (aliases excluded)."""
    return list(_BUILDERS)


def _key(name: str) -> str:
    """The library key ``name`` stands for (case, spaces, "-" and aliases normalised)."""
    key = name.strip().lower().replace(" ", "_")
    key = ALIASES.get(key, key)
    if key not in _BUILDERS:
        key2 = key.replace("-", "_")
        key = ALIASES.get(key2, key2)
    return key


def get(name: str) -> Material:
    """The library material ``name`` (case-insensitive; "-" and " " read as "_").

    Raises :class:`~warpoptics.errors.InputError` with the closest names for an unknown one.
    """
    if not isinstance(name, str):
        raise InputError("material name must be a string", field="material", value=name)
    key = _key(name)
    if key not in _BUILDERS:
        close = difflib.get_close_matches(key, list(_BUILDERS) + list(ALIASES), n=3, cutoff=0.5)
        hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
        raise InputError(
            f"unknown material{hint}", field="material", value=name, allowed=", ".join(_BUILDERS)
        )
    if key not in _cache:
        _cache[key] = _BUILDERS[key]()
    return _cache[key]
