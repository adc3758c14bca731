"""Sphinx extension: the scene-file reference, generated from the validators at build time.

``.. scene-reference:: camera`` (or ``bench``, ``microscope``) inserts one table per scene table of
that kind, read by :func:`warpoptics.scene.reference.tables`: keys, types, units, ranges and
defaults come from the code, the descriptions from its :data:`~warpoptics.scene.reference.FIELDS`.
"""

from __future__ import annotations

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

_CACHE: dict[str, list] = {}


def _tables() -> list:
    if "tables" not in _CACHE:
        from warpoptics.scene.reference import tables

        _CACHE["tables"] = tables()
    return _CACHE["tables"]


def _text(text: str) -> str:
    """Plain text in a table cell; a lone "-" (no unit) would start a bullet list."""
    return "\\" + text if text.startswith(("-", "+", "*")) else text


def _cell(text: str) -> str:
    return f"``{text}``" if text else ""


def table_rst(table) -> list[str]:
    """The reST of one scene table: a title, its intro and a list-table of its keys."""
    title = table.name
    lines = [title, "~" * max(len(title), 3), "", table.intro, ""]
    lines += [
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 16 9 8 22 12 33",
        "",
        "   * - key",
        "     - type",
        "     - unit",
        "     - range",
        "     - default",
        "     - description",
    ]
    for r in table.rows:
        lines += [
            f"   * - ``{r.key}``",
            f"     - {r.type}",
            f"     - {_text(r.unit)}",
            f"     - {_cell(r.range)}",
            f"     - {_cell(r.default)}",
            f"     - {_text(r.description)}",
        ]
    return lines + [""]


class SceneReference(SphinxDirective):
    """``.. scene-reference:: KIND``: every table of one scene kind (camera, bench, microscope)."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        kind = self.arguments[0]
        chosen = [t for t in _tables() if t.scene_kind == kind]
        if not chosen:
            raise self.error(f"no scene tables of kind {kind!r}")
        lines: list[str] = []
        for t in chosen:
            lines += table_rst(t)
        container = nodes.section()
        nested_parse_with_titles(
            self.state, StringList(lines, source="warpoptics.scene.reference"), container
        )
        return container.children


def _always_reread(app, env, added, changed, removed) -> list[str]:
    """The pages with a reference read the code, which Sphinx does not watch: read them again."""
    return [name for name in env.found_docs if name == "reference/scene"]


def setup(app):
    app.add_directive("scene-reference", SceneReference)
    app.connect("env-get-outdated", _always_reread)
    return {"version": "1", "parallel_read_safe": True}
