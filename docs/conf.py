"""Sphinx configuration of the warpoptics documentation (built by `.ci/run`, README: docs)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "warpoptics"
author = "the warpoptics authors"
copyright = "the warpoptics authors"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "scene_reference",
    "api_pages",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "notebook.ipynb", "gallery/grading/*"]
autodoc_mock_imports: list[str] = []
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3

html_theme = "furo"
html_title = "warpoptics"

# numpydoc-style docstrings, as colour-science writes them
napoleon_google_docstring = True
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": False}
autosummary_generate = False
# a short name in a docstring that two modules define (chromophores) stays plain text
suppress_warnings = ["ref.python"]
