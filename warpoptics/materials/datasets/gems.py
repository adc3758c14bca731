"""The gem library's data: where each material's index comes from, and its absorption, as plain data.

Each entry's fields are described above :data:`GEMS`.

Provenance
----------
- refractiveindex.info database pages as named (authors in the page names: Peter, Malitson,
  Ghosh, Tropf, Wood & Nassau 1982 (cubic zirconia stabilised with 12 mol % yttria), Wang
  (6H-SiC), Daimon (water, 20 °C), SCHOTT (N-BK7)).
- GIA Gem Reference Guide (1995) and R. Webster, *Gems*, 5th ed. (1994), property tables:
  zircon (high) n_o 1.925, n_e 1.984, dispersion 0.039; emerald n_o 1.583, n_e 1.577, 0.014;
  topaz n_α 1.619, n_γ 1.627, 0.014; peridot dispersion 0.020; andalusite 0.016.
- J. W. Anthony, R. A. Bideaux, K. W. Bladh, M. C. Nichols (eds.), *Handbook of Mineralogy*,
  Mineralogical Society of America (Mineral Data Publishing, 2001): forsterite α 1.635, β 1.651,
  γ 1.670, 2V(meas.) 82°, biaxial (+); andalusite α 1.632, β 1.636, γ 1.643, 2V(meas.) 71°–86°,
  biaxial (−) or (+), pleochroism X reddish pink, Y = Z greenish yellow; topaz α 1.606–1.634,
  β 1.609–1.637, γ 1.616–1.644, 2V(meas.) 48°–68°, biaxial (+).  W. A. Deer, R. A. Howie,
  J. Zussman, *An Introduction to the Rock-Forming Minerals* (1992), olivine: optically positive
  from Fo85 to Fo100 with 2V_z 90° to 82° (as quoted by the MINTS database, mints.uwc.ac.za).
- S. Guy, C. Soler, ACM TOG 23(3) 2004, §6.1 table (garnet, tourmaline, peridot, andalusite,
  and the absorbances of diamond and sapphire).

Ruby, emerald and alexandrite are chromophore varieties (:mod:`.varieties`, band sets in
:mod:`.chromophores`); alexandrite takes its index from its entry here.
"""

from __future__ import annotations

__all__ = ["GEMS", "CR3_BANDS_SOURCE", "BIAXIAL_SOURCES"]

#: provenance of the biaxial entries (indices, 2V, sign)
BIAXIAL_SOURCES = (
    "GIA Gem Reference Guide (1995), property tables (RI ranges, birefringence, optic sign); "
    "J. W. Anthony et al., Handbook of Mineralogy, Mineralogical Society of America (2V(meas.) "
    "ranges); M. O'Donoghue, Gems, 6th ed. (2006) (tanzanite n_alpha/n_beta/n_gamma, band "
    "positions 595/528/455 nm); refractiveindex.info main/BeAl2O4/Walling-alpha/-beta/-gamma "
    "(Walling et al. 1980, IEEE JQE 16, 1302; formula of Loiko & Major 2016, OME 6, 2177) for "
    "alexandrite; chrysoberyl: Deutsche Gemmologische Gesellschaft indices, Handbook of Mineralogy "
    "2V(meas.) 70°; peridot (forsterite), andalusite, topaz: Handbook of Mineralogy indices / 2V "
    "ranges (topaz n_beta from its range ends), olivine 2V_z 82°-90° for Fo85-Fo100 (Deer, Howie & "
    "Zussman 1992), GIA dispersions"
)

#: the source string of every Cr³⁺ band spectrum
CR3_BANDS_SOURCE = "Cr3+ bands (positions: literature; amplitudes illustrative)"

#: Each entry of :data:`GEMS` (in library order) has
#:
#: ``index``     how n(λ) is obtained:
#:               ``("page", page)``: a refractiveindex.info page (read offline), isotropic;
#:               ``("pages", o_page, e_page)``: the ordinary and extraordinary pages of a uniaxial
#:               crystal (optic axis +z);
#:               ``("constants", n_o, n_e, dispersion)``: gemological constants at the sodium D line
#:               and the dispersion n(430.8) − n(686.7), fitted by a two-term Cauchy formula;
#:               ``("guy_soler_2004",)``: the indices of the Guy & Soler §6.1 table
#:               (:mod:`.guy_soler_2004`);
#:               ``("biaxial", n_alpha, n_beta, n_gamma, dispersion)``: the three principal indices
#:               at the sodium D line, each a Cauchy fit with the one dispersion;
#:               ``("biaxial_pages", alpha_page, beta_page, gamma_page)``: three refractiveindex.info
#:               pages (principal axes X, Y, Z of the object frame)
#: ``two_v``     biaxial: the literature optic-axial angle ``(low, high, sign, source)`` (degrees; the
#:               range is the stated uncertainty) that the indices must reproduce
#: ``source``    the provenance string the material carries (index entries other than "page")
#: ``guy_soler_row``
#:               the row of the Guy & Soler §6.1 table an entry takes its ``("guy_soler_2004",)``
#:               indices and its ``"guy_soler_2004"`` absorbances from (default: the entry's own name)
#: ``absorption`` absent (colourless, k = 0), ``"guy_soler_2004"`` (the §6.1 absorbances), or
#:               ``{"o": bands, "e": bands, "source": ...}`` with bands (centre nm, width nm,
#:               peak alpha 1/mm) of Gaussian profiles; biaxial: ``{"x": ..., "y": ..., "z": ...,
#:               "source": ...}`` for D along X, Y, Z, each bands or ``"o"`` / ``"e"``: that Guy & Soler
#:               §6.1 spectrum (eq. 9 inversion) of the row named by ``guy_soler_row`` (and its triplet
#:               for rgb3)
GEMS: dict[str, dict] = {
    "diamond": dict(index=("page", "main/C/Peter"), absorption="guy_soler_2004"),
    "sapphire": dict(
        index=("pages", "main/Al2O3/Malitson-o", "main/Al2O3/Malitson-e"),
        source="refractiveindex.info main/Al2O3/Malitson-o/-e",
        absorption="guy_soler_2004",
    ),
    "calcite": dict(
        index=("pages", "main/CaCO3/Ghosh-o", "main/CaCO3/Ghosh-e"),
        source="refractiveindex.info main/CaCO3/Ghosh-o/-e",
    ),
    "quartz": dict(
        index=("pages", "main/SiO2/Ghosh-o", "main/SiO2/Ghosh-e"),
        source="refractiveindex.info main/SiO2/Ghosh-o/-e",
    ),
    "zircon": dict(
        index=("constants", 1.925, 1.984, 0.039),
        source="high zircon, GIA: n_o 1.925, n_e 1.984 (nD), dispersion 0.039; Cauchy fit",
    ),
    "tourmaline": dict(index=("guy_soler_2004",), absorption="guy_soler_2004"),
    # peridot, andalusite and topaz are biaxial (below); the *_uniaxial entries keep Guy & Soler's
    # uniaxial model (the paper's §6.1 indices and absorbances, n_o / n_e = two of the three
    # principal indices)
    "peridot_uniaxial": dict(index=("guy_soler_2004",), absorption="guy_soler_2004", guy_soler_row="peridot"),
    "garnet": dict(index=("guy_soler_2004",), absorption="guy_soler_2004"),
    "spinel": dict(index=("page", "main/MgAl2O4/Tropf")),
    "topaz_uniaxial": dict(
        index=("constants", 1.619, 1.627, 0.014),
        source=(
            "topaz (biaxial, treated as uniaxial): n_alpha 1.619 -> o, n_gamma 1.627 -> e (nD), "
            "dispersion 0.014 (GIA); Cauchy fit"
        ),
    ),
    "cubic_zirconia": dict(index=("page", "main/ZrO2/Wood")),
    "moissanite": dict(
        index=("pages", "main/SiC/Wang-6H-o", "main/SiC/Wang-6H-e"),
        source="refractiveindex.info main/SiC/Wang-6H-o/-e (6H-SiC), extrapolated below 435.8 nm",
    ),
    "andalusite_uniaxial": dict(
        index=("guy_soler_2004",), absorption="guy_soler_2004", guy_soler_row="andalusite"
    ),
    # biaxial stones (optics/biaxial.py): principal axes X, Y, Z = the object's x, y, z by default
    "tanzanite": dict(
        index=("biaxial", 1.692, 1.694, 1.700, 0.019),
        source=(
            "tanzanite (zoisite), GIA: RI 1.691-1.700, biaxial (+), dispersion 0.019; n_alpha 1.692, "
            "n_gamma 1.700 (O'Donoghue 2006), n_beta 1.694 within GIA's range; Cauchy fits"
        ),
        two_v=(50.0, 69.0, "+", "Handbook of Mineralogy, zoisite: 2V(meas.) up to 69° (+)"),
        absorption=dict(
            x=((528.0, 45.0, 0.45), (455.0, 30.0, 0.05)),
            y=((595.0, 55.0, 0.70), (528.0, 30.0, 0.10)),
            z=((455.0, 45.0, 0.55), (400.0, 40.0, 0.40)),
            source=(
                "V3+ bands at 595/528/455 nm (O'Donoghue 2006); their assignment to D along X "
                "(red-violet), Y (blue), Z (yellow-bronze) and the strengths are an illustrative fit"
            ),
        ),
    ),
    "iolite": dict(
        index=("biaxial", 1.542, 1.547, 1.551, 0.017),
        source=(
            "iolite (cordierite), GIA: RI 1.542-1.551, biaxial (-), dispersion 0.017; n_beta 1.547 "
            "within the range; Cauchy fits"
        ),
        two_v=(35.0, 106.0, "-", "Handbook of Mineralogy, cordierite: 2V(meas.) 35°-106° (-)"),
        absorption=dict(
            x=((430.0, 50.0, 0.12),),
            y=((560.0, 70.0, 0.25),),
            z=((600.0, 80.0, 0.55),),
            source=(
                "Fe2+-Fe3+ charge-transfer band near 590 nm strongest for D along Z (blue), weaker "
                "along Y (violet), a weak blue band along X (pale yellow); illustrative fit"
            ),
        ),
    ),
    "chrysoberyl": dict(
        index=("biaxial", 1.746, 1.749, 1.755, 0.015),
        source=(
            "chrysoberyl: n_alpha 1.746, n_beta 1.749, n_gamma 1.755 (nD; Deutsche Gemmologische "
            "Gesellschaft table, as quoted by diamantlabor.com/chysoberyll.html), biaxial (+), "
            "dispersion 0.015 (GIA, gemstones-guide.com chrysoberyl properties); Cauchy fits"
        ),
        # Handbook of Mineralogy, chrysoberyl (Mineral Data Publishing 2001): alpha 1.746,
        # beta 1.748, gamma 1.756, 2V(meas.) = 70°, biaxial (+), r > v; it states no
        # uncertainty: ±5° is assumed here (its own 3-decimal indices give 53°, so the measured
        # angle, not those indices, is the reference)
        two_v=(65.0, 75.0, "+", "Handbook of Mineralogy, chrysoberyl: 2V(meas.) = 70° (+)"),
    ),
    "alexandrite": dict(
        index=("biaxial_pages", "main/BeAl2O4/Walling-γ", "main/BeAl2O4/Walling-α", "main/BeAl2O4/Walling-β"),
        source=(
            "refractiveindex.info main/BeAl2O4/Walling-γ, -α, -β as n_alpha, n_beta, n_gamma "
            "(Cr-doped chrysoberyl, the alexandrite laser crystal; 2V 61° (+) from these indices)"
        ),
        # no 2V check: the pages (Walling et al. 1980 via Loiko & Major 2016; a synthetic
        # Czochralski laser crystal) give n_beta - n_alpha = 0.0019 of n_gamma - n_alpha = 0.0076
        # at 589.3 nm, hence 2V = 61.1° with r < v (62.7° at 450 nm, 61.0° at 700 nm), where the
        # Handbook of Mineralogy gives 70° and r > v for natural chrysoberyl.  Sorting the pages
        # by index is the only order they allow (the page labelled gamma is the lowest), so the
        # gap is in the data, not the axis assignment; the pages are kept for their measured
        # dispersion, chrysoberyl above carries the gem constants
        two_v=None,
        # the colour of alexandrite is the chromophore variety's (datasets/varieties.py: Cr3+ in
        # chrysoberyl, datasets/chromophores/chrysoberyl.py), built on this entry's index
    ),
    "peridot": dict(
        index=("biaxial", 1.635, 1.651, 1.670, 0.020),
        source=(
            "peridot (forsterite-rich olivine): n_alpha 1.635, n_beta 1.651, n_gamma 1.670 (Handbook of "
            "Mineralogy, forsterite), biaxial (+), dispersion 0.020 (GIA); Cauchy fits"
        ),
        # the Handbook gives 2V(meas.) = 82° without an uncertainty; its own 3-decimal indices
        # give 86.0° (±1.6° for ±0.0005 on n_beta).  The range checked is Deer, Howie & Zussman's
        # 2V_z for the optically positive olivines (Fo85-Fo100: 90° down to 82°)
        two_v=(
            82.0,
            90.0,
            "+",
            "Handbook of Mineralogy, forsterite: 2V(meas.) 82° (+); Deer, Howie & Zussman 1992: "
            "2V_z 82°-90° for Fo100-Fo85",
        ),
        absorption=dict(
            x="e",
            y="o",
            z="o",
            source=(
                "Guy & Soler 2004 §6.1 peridot triplets, eq. 9 inversion (a fit, not a measured "
                "spectrum): K^e for D along X (its n_e 1.640 is the low index n_alpha), K^o for Z "
                "(n_o 1.680 ~ n_gamma) and for Y (the paper's 'two of the three spectra nearly "
                "identical'; the stronger one, as olivine absorbs most for D along Y)"
            ),
        ),
        guy_soler_row="peridot",
    ),
    "andalusite": dict(
        index=("biaxial", 1.632, 1.636, 1.643, 0.016),
        source=(
            "andalusite: n_alpha 1.632, n_beta 1.636, n_gamma 1.643 (Handbook of Mineralogy), "
            "dispersion 0.016 (GIA); Cauchy fits"
        ),
        # the Handbook: "Biaxial (-) or (+)", 2V(meas.) 71°-86°; its indices give 74.5° with Z
        # the acute bisectrix (+).  Gem references (GIA) call gem andalusite negative: a
        # negative stone needs n_beta > 1.6375 with these n_alpha, n_gamma
        two_v=(71.0, 86.0, "+", "Handbook of Mineralogy, andalusite: 2V(meas.) 71°-86°, (-) or (+)"),
        absorption=dict(
            x="o",
            y="e",
            z="e",
            source=(
                "Guy & Soler 2004 §6.1 andalusite triplets, eq. 9 inversion (a fit, not a measured "
                "spectrum): K^o for D along X (its n_o 1.635 ~ n_alpha), K^e for Z (n_e 1.644 ~ "
                "n_gamma) and Y (Handbook of Mineralogy pleochroism: Y = Z)"
            ),
        ),
        guy_soler_row="andalusite",
    ),
    "topaz": dict(
        index=("biaxial", 1.619, 1.621, 1.627, 0.014),
        source=(
            "topaz: n_alpha 1.619, n_gamma 1.627 (nD), dispersion 0.014 (GIA); n_beta 1.621 = n_alpha "
            "+ 0.002, the beta - alpha of the Handbook of Mineralogy's index ranges (0.003 at its low "
            "end, 0.002-0.003 at its high end), not a measurement; biaxial (+); Cauchy fits"
        ),
        # n_beta is not measured for this stone, so this check is one of consistency: the Handbook's
        # 2V range (48° F-rich to 68° OH-richer) holds n_beta within 1.6204-1.6214 here
        two_v=(48.0, 68.0, "+", "Handbook of Mineralogy, topaz: 2V(meas.) 48°-68° (+)"),
    ),
    "kyanite": dict(
        index=("biaxial", 1.713, 1.722, 1.729, 0.020),
        source="kyanite, GIA: RI 1.713-1.729 (n_alpha, n_gamma), biaxial (-), dispersion 0.020; "
        "n_beta 1.722 within the handbook range 1.720-1.725; Cauchy fits",
        two_v=(78.0, 83.0, "-", "Handbook of Mineralogy, kyanite: 2V(meas.) 78°-83° (-)"),
    ),
    "water": dict(index=("page", "main/H2O/Daimon-20.0C")),
    "bk7": dict(index=("page", "specs/SCHOTT-optical/N-BK7")),
    "fused_silica": dict(index=("page", "main/SiO2/Malitson")),
}
