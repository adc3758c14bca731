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


def test_every_gallery_image_is_shown_with_its_command():
    page = (ROOT / "docs/gallery.md").read_text()
    sections = page.split("\n### ")[1:]
    shown = {}
    for section in sections:
        for image in (part.split(")")[0] for part in section.split("](gallery/")[1:]):
            shown[image] = section
    images = sorted(p.name for p in (ROOT / "docs/gallery").glob("*.png"))
    assert images
    assert not set(images) - set(shown), f"images the gallery page does not show: {set(images) - set(shown)}"
    assert not set(shown) - set(images), f"the gallery page shows missing images: {set(shown) - set(images)}"
    for image, section in shown.items():
        assert "```bash\n" in section and ("warpoptics " in section or "python scripts/" in section), image


def test_the_pages_name_files_that_exist():
    """Every scene, script and test file a documentation page names exists."""
    import re

    missing = []
    for page in sorted((ROOT / "docs").rglob("*.md")):
        if "_build" in page.parts:
            continue
        text = page.read_text()
        for path in re.findall(r"(?:scenes|scripts|tests)/[\w/.-]+\.(?:toml|exr|py|asc)", text):
            if not (ROOT / path).is_file():
                missing.append(f"{page.relative_to(ROOT)}: {path}")
    assert not missing, missing
