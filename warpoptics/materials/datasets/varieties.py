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
