"""The scene-file reference of the documentation is generated from the validators and complete.

``warpoptics.scene.reference`` reads every table's keys, ranges and defaults from the
validators; each key's type, unit and description live in its ``FIELDS``. These tests fail when
a validator accepts a key that has no description or unit, when a description names a key no
validator accepts, and when the page the documentation builds leaves a key out.
"""

import importlib.util
from pathlib import Path

import pytest

from warpoptics.errors import InputError
from warpoptics.scene import Scene
from warpoptics.scene import reference as ref

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def tables():
    return ref.tables()


def _extension():
    spec = importlib.util.spec_from_file_location("scene_reference", ROOT / "docs/_ext/scene_reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_key_has_type_unit_and_description(tables):
    missing = [
        f"{t.name}: {r.key}"
        for t in tables
        for r in t.rows
        if not (r.type in ref.TYPES and r.unit and r.description)
    ]
    assert not missing, "describe these keys in warpoptics/scene/reference.py FIELDS:\n" + "\n".join(missing)
    assert ref.undocumented() == []


def test_no_description_of_a_key_that_does_not_exist():
    assert ref.stale() == []


def test_the_tables_cover_every_scene_kind(tables):
    names = {t.name for t in tables}
    for name in ("[camera]", "[render]", "[[object]]", "[source]", "[[sensor]]", "[microscope]", "[sample]"):
        assert name in names
    assert {t.scene_kind for t in tables} == {"camera", "bench", "microscope"}
    assert '[[object]] shape = "round_brilliant"' in names


def test_keys_ranges_and_defaults_come_from_the_validators(tables):
    render = {r.key: r for t in tables if t.name == "[render]" for r in t.rows}
    # the keys are what [render] accepts: every RenderConfig field a scene may set
    assert set(render) == set(Scene.load(ROOT / "scenes/diamond.toml").render.__dataclass_fields__) - {
        "source"
    }
    # a range is what the validator refuses beyond: spp 0 is refused, its lower bound 1 accepted
    assert render["spp"].range.startswith(">= 1")
    with pytest.raises(InputError):
        Scene.from_dict({"object": [{"shape": "sphere"}], "render": {"spp": 0}})
    Scene.from_dict({"object": [{"shape": "sphere"}], "render": {"spp": 1}})
    # choices list every allowed value, defaults are the config's
    assert "stratified" in render["spectral"].range and render["spectral"].default == '"stratified"'
    assert render["wavelengths"].default == "45"
    camera = {r.key: r for t in tables if t.name == "[camera]" for r in t.rows}
    assert camera["fov"].unit == "degrees" and camera["width"].default == "512"


def test_the_generated_page_lists_every_key(tables):
    ext = _extension()
    for t in tables:
        text = "\n".join(ext.table_rst(t))
        assert t.name in text
        for r in t.rows:
            assert f"``{r.key}``" in text, (t.name, r.key)
    page = (ROOT / "docs/reference/scene.rst").read_text()
    for kind in ("camera", "bench", "microscope"):
        assert f".. scene-reference:: {kind}" in page
