"""The documentation site: every public name of the API has a page that documents it.

``docs/_ext/api_pages.py`` writes one page per module with an ``__all__`` when the site is built;
a name re-exported by a package is documented on the page of the module that defines it. These
tests run the generator without Sphinx's build (``.ci/run`` builds the whole site).
"""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def api():
    spec = importlib.util.spec_from_file_location("api_pages", ROOT / "docs/_ext/api_pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def names(api):
    return api.public_names()


def test_every_public_name_has_a_page(api, names):
    missing = []
    for module, rows in names.items():
        for name, (kind, page) in rows.items():
            if kind == "module":
                continue
            if page not in names or name not in names[page]:
                missing.append(f"{module}.{name} -> {page}")
    assert not missing, missing


def test_the_pages_document_each_name(api, names):
    for module in ("warpoptics.optics.fresnel", "warpoptics.optics.jones", "warpoptics.scene.load"):
        text = api.module_page(module, names[module])
        for name, (kind, page) in names[module].items():
            if page == module and kind != "module":
                assert f"{module}.{name}" in text or f":: {name}" in text, (module, name)
    top = api.module_page("warpoptics", names["warpoptics"])
    # the top-level second paths (wo.render, wo.Scene) link to their homes instead of repeating them
    assert names["warpoptics"]["render"][1] == "warpoptics.pipelines.render"
    assert "warpoptics.pipelines.render" in top


def test_a_docstring_that_is_not_rest_is_shown_as_written(api):
    assert api._parses("A law.\n\nParameters\n----------\nx : float\n    metres\n")
    assert not api._parses("an inline ``literal without its end\n")
    doc = api._clean_doc("broken ``literal\n\n  indented oddly\nback")
    assert doc.startswith("::")
