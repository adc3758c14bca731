"""Named gem varieties as chromophores in a host crystal, with the source of each concentration.

Each entry of :data:`VARIETIES` is a library material (``warpoptics.materials.get(name)``):

``host``            a host of :mod:`.chromophores` (its colourless index and its band sets)
``concentrations``  {chromophore: concentration in that band set's unit}, typical of the variety
``source``          where the typical concentrations come from (analyses of real stones)
``orientation``     how the stone is usually cut relative to the optic axis / principal axes
                    and the pleochroic colours, as plain text
``index``           optional: the index entry (:data:`.gems.GEMS` format) in place of the host's

A scene overrides a variety's concentrations with ``material = { base = "ruby", chromophores =
{ Cr = 0.4 } }`` (so ``object.0.material.chromophores.Cr`` is a sweep axis).
"""

from __future__ import annotations

__all__ = ["VARIETIES"]

VARIETIES: dict[str, dict] = {}

# chromophore-B hosts (quartz, olivine, zoisite, cordierite, tourmaline, topaz, zircon).  Where the
# band set's unit is a peak alpha (no measured absorption coefficient was available, see each host
# module), the value is chosen so that a 5 mm plate shows the variety's trade colour under D65.
_CHOSEN = "strength chosen to give the trade colour (no measured absorption coefficient available)"

VARIETIES.update(
    amethyst=dict(
        host="quartz",
        concentrations={"amethyst centre": 0.2},
        source=f"amethyst centre {_CHOSEN}",
        orientation=(
            "usually cut with the table near perpendicular to c (face up mostly o-ray); dichroic "
            "bluish purple (o) / reddish purple (e)"
        ),
    ),
    citrine=dict(
        host="quartz",
        concentrations={"Fe3+": 1.0},
        source=f"Fe3+ edge {_CHOSEN}",
        orientation="weakly dichroic; no preferred orientation",
    ),
    peridot=dict(
        host="olivine",
        concentrations={"Fe2+": 9.16, "Fe3+": 0.4},
        source=(
            "Fe2+: 9.16 wt% FeO, the microprobe analysis of the Fo89 olivine GDS70 (USGS spectral "
            f"library, Clark et al. 2003); Fe3+ edge {_CHOSEN}"
        ),
        orientation="weakly trichroic yellowish green; usually cut for weight, no preferred axis",
    ),
    tanzanite=dict(
        host="zoisite",
        concentrations={"V3+": 0.4},
        source=f"heated tanzanite (no 455 nm band); V3+ {_CHOSEN}",
        orientation=(
            "heated: X red-violet, Y blue, Z violet; usually cut with the table perpendicular to Z "
            "or Y for a blue-violet face up"
        ),
    ),
    iolite=dict(
        host="cordierite",
        concentrations={"Fe2+-Fe3+": 2.0, "Fe2+": 2.0},
        source=(
            "2 wt% FeO, within the 1.68-4.60 wt% of gem cordierite (Crystals 14(7), 637 (2024), "
            "table 2); the band strengths per wt% FeO are chosen"
        ),
        orientation="X pale yellow, Y violet, Z blue; cut with the table perpendicular to X for blue",
    ),
    rubellite=dict(
        host="tourmaline",
        concentrations={"Mn3+": 0.8},
        source=f"Mn3+ {_CHOSEN}",
        orientation="o (E⊥c) deeper than e; the table usually parallel to c",
    ),
    green_tourmaline=dict(
        host="tourmaline",
        concentrations={"Fe2+": 1.0, "Fe2+-Fe3+": 0.5, "Fe2+-Ti4+": 0.15},
        source=f"iron-bearing elbaite; FeO values and Fe2+-Ti4+ {_CHOSEN}",
        orientation="o (E⊥c) far darker (closed c axis); the table parallel to c",
    ),
    paraiba_tourmaline=dict(
        host="tourmaline",
        concentrations={"Cu2+": 2.0},
        source=(
            "2.0 wt% CuO, within the 1.5-2.3 wt% CuO of turquoise-blue Batalha-mine elbaite "
            "(Mineralogical Record, cuprian elbaite); the band strength per wt% CuO is chosen"
        ),
        orientation="o (E⊥c) stronger; the table usually parallel to c",
    ),
    imperial_topaz=dict(
        host="topaz",
        concentrations={"Cr": 0.3, "colour centre": 0.5},
        source=f"Cr bands and colour-centre edge {_CHOSEN}",
        orientation="pleochroic orange / light orange; usually long cuts along c",
    ),
    blue_zircon=dict(
        host="zircon",
        concentrations={"blue centre": 0.8},
        source=f"heat-treated blue zircon; blue centre {_CHOSEN}",
        orientation="o-ray blue, e-ray near colourless; cut with the table perpendicular to c",
    ),
)
