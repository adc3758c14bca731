"""Scene files (TOML) -> validated frozen configs.

:mod:`.schema` (the tables of a camera scene), :mod:`.coating` (the one coating / film schema),
:mod:`.load` (:class:`Scene`: load, overrides), :mod:`.bench` (optical-bench scenes).  Values are
checked with the one toolkit :mod:`warpoptics.validate`.
"""

from . import bench, coating, load, schema
from .load import Scene, set_dotted  # noqa: F401  (attributes for ``from warpoptics.scene import Scene``)

__all__ = ["bench", "coating", "load", "schema"]
