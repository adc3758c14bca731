"""Material data, apart from the code that computes with it (as colour-science keeps its data under
``datasets/``): the gem library's entries (:mod:`.gems`: refractiveindex.info pages, gemological
constants, Cr³⁺ bands), the Guy & Soler gem table (:mod:`.guy_soler_2004`) and the dye solutions' data
(:mod:`.dyes`), each with its provenance.

Kept as Python modules of plain literals rather than TOML/CSV package data: the values are short
tables of numbers with a provenance comment per entry, a diff shows each changed value beside its
source, they need no loader or schema code and no package-data configuration, and they import
without touching the file system.  Nothing here imports a computing module.
"""

__all__: list[str] = []
