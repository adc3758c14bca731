"""Sphinx extension: one API page per public module of warpoptics, generated at build time.

Every module of the package that declares ``__all__`` gets a page in ``docs/api/generated/``
listing the names of its ``__all__`` that live there: functions and classes are documented where
they are defined (a package that re-exports them links to that page instead of repeating it),
Warp device functions and structs with their signature and docstring, constants by name and
docstring. :func:`public_names` says which page shows each name (``tests/test_docs.py`` checks
that every public name has one). The command-line modules are the ``warpoptics`` command, whose
reference is ``warpoptics --help``.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from pathlib import Path

import docutils.core
import docutils.utils

#: modules whose names are not Python API (the command line: ``warpoptics COMMAND --help``)
SKIPPED_PREFIXES = ("warpoptics.cli", "warpoptics.commands")
OUT = Path(__file__).resolve().parents[1] / "api" / "generated"


def public_modules() -> list:
    """Every module of warpoptics with an ``__all__``, in the order ``pkgutil`` walks them."""
    import warpoptics

    mods = [warpoptics]
    for info in pkgutil.walk_packages(warpoptics.__path__, "warpoptics."):
        if info.name.startswith(SKIPPED_PREFIXES):
            continue
        mod = importlib.import_module(info.name)
        if hasattr(mod, "__all__"):
            mods.append(mod)
    return mods


def _warp_type(obj) -> str | None:
    """``"Function"`` or ``"Struct"`` for Warp's device functions and structs."""
    t = type(obj)
    return t.__name__ if t.__module__.startswith("warp.") and t.__name__ in ("Function", "Struct") else None


def _kind(obj) -> str:
    if inspect.ismodule(obj):
        return "module"
    if _warp_type(obj) == "Function":
        return "wp_function"
    if _warp_type(obj) == "Struct":
        return "wp_struct"
    if inspect.isclass(obj):
        return "class"
    if inspect.isroutine(obj) or callable(obj) and hasattr(obj, "__wrapped__"):
        return "function"
    return "data"


def _home(obj, kind: str, module_all: dict[str, set]) -> str | None:
    """The module that defines ``obj`` when it lists it in its ``__all__`` (None otherwise)."""
    if kind in ("function", "class"):
        name = getattr(obj, "__module__", None)
    elif kind == "wp_function":
        name = getattr(obj.func, "__module__", None)
    elif kind == "wp_struct":
        name = getattr(obj.cls, "__module__", None)
    else:
        return None
    own = getattr(obj, "__name__", None) or getattr(obj, "key", None)
    if kind == "wp_struct":
        own = obj.cls.__name__
    return name if name in module_all and own in module_all[name] else None


def public_names() -> dict[str, dict[str, tuple[str, str]]]:
    """``{module: {name: (kind, page module)}}`` for every name of every ``__all__``: the page
    that documents it (its own module, or the module that defines it)."""
    mods = public_modules()
    module_all = {m.__name__: set(m.__all__) for m in mods}
    out: dict[str, dict[str, tuple[str, str]]] = {}
    for mod in mods:
        rows = {}
        for name in mod.__all__:
            obj = getattr(mod, name)
            kind = _kind(obj)
            if kind == "module":
                page = obj.__name__
            else:
                home = _home(obj, kind, module_all)
                page = home if home is not None else mod.__name__
            rows[name] = (kind, page)
        out[mod.__name__] = rows
    return out


def _clean_doc(doc: str | None) -> str:
    """A docstring as reST: as written when docutils reads it without complaint, else as a
    literal block (a docstring written for the terminal, not for reST)."""
    from sphinx.ext.napoleon import Config
    from sphinx.ext.napoleon.docstring import NumpyDocstring

    if not doc:
        return ""
    text = str(NumpyDocstring(inspect.cleandoc(doc), Config(napoleon_use_rtype=False)))
    return (
        text
        if _parses(text)
        else "::\n\n" + "\n".join("    " + line for line in inspect.cleandoc(doc).splitlines())
    )


def _parses(text: str) -> bool:
    settings = {
        "report_level": 2,
        "halt_level": 5,
        "warning_stream": _Sink(),
        "file_insertion_enabled": False,
    }
    sink = settings["warning_stream"]
    try:
        docutils.core.publish_doctree(text, settings_overrides=settings)
    except Exception:  # noqa: BLE001 - any failure to parse means: show it as written
        return False
    return not sink.written


class _Sink:
    def __init__(self) -> None:
        self.written = False

    def write(self, text: str) -> None:
        # roles and directives that only Sphinx knows are fine; real reST errors are not
        if "Unknown interpreted text role" in text or "Unknown directive type" in text:
            return
        if text.strip():
            self.written = True


def _indent(text: str, n: int = 3) -> str:
    return "\n".join((" " * n + line) if line.strip() else "" for line in text.splitlines())


def _signature(func) -> str:
    try:
        return str(inspect.signature(func)).replace("\n", " ")
    except (TypeError, ValueError):
        return "(...)"


def module_page(modname: str, rows: dict[str, tuple[str, str]]) -> str:
    """The reST of one module's page."""
    mod = importlib.import_module(modname)
    title = f"``{modname}``"
    lines = [title, "=" * len(title), "", f".. py:module:: {modname}", ""]
    doc = _clean_doc(mod.__doc__)
    if doc:
        lines += [doc, ""]
    elsewhere = sorted((n, page) for n, (kind, page) in rows.items() if page != modname and kind != "module")
    submodules = sorted(n for n, (kind, _p) in rows.items() if kind == "module")
    submodules = [n for n in submodules if hasattr(getattr(mod, n), "__all__")]
    if submodules:
        lines += ["Submodules: " + ", ".join(f":doc:`{rows[n][1]}`" for n in submodules), ""]
    if elsewhere:
        lines += [
            "Also importable from here: " + ", ".join(f":doc:`{n} <{page}>`" for n, page in elsewhere),
            "",
        ]
    for name, (kind, page) in rows.items():
        if page != modname or kind == "module":
            continue
        obj = getattr(mod, name)
        full = f"{modname}.{name}"
        if kind == "function":
            lines += [f".. autofunction:: {full}", ""]
        elif kind == "class":
            lines += [f".. autoclass:: {full}", "   :members:", ""]
        elif kind == "wp_function":
            lines += [f".. py:function:: {name}{_signature(obj.func)}", "", "   Warp device function.", ""]
            lines += [_indent(_clean_doc(obj.func.__doc__)), ""]
        elif kind == "wp_struct":
            lines += [f".. py:class:: {name}", "", "   Warp struct.", ""]
            lines += [_indent(_clean_doc(obj.cls.__doc__)), ""]
        else:
            lines += [f".. py:data:: {name}", f"   :type: {type(obj).__name__}", ""]
    return "\n".join(lines) + "\n"


def write_pages(app=None) -> None:
    """Write ``docs/api/generated/<module>.rst`` for every public module (only changed files)."""
    OUT.mkdir(parents=True, exist_ok=True)
    wanted = set()
    for modname, rows in public_names().items():
        path = OUT / f"{modname}.rst"
        wanted.add(path.name)
        text = module_page(modname, rows)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    for old in OUT.glob("*.rst"):
        if old.name not in wanted:
            old.unlink()


def _literal_if_not_rest(app, what, name, obj, options, lines) -> None:
    """``autodoc-process-docstring`` after napoleon: a docstring docutils cannot read as reST is
    shown as written (a literal block) instead of failing the build."""
    if lines and not _parses("\n".join(lines)):
        original = inspect.cleandoc(getattr(obj, "__doc__", None) or "\n".join(lines))
        lines[:] = ["::", ""] + ["    " + line for line in original.splitlines()] + [""]


def setup(app):
    app.setup_extension("sphinx.ext.napoleon")
    app.connect("builder-inited", write_pages)
    app.connect("autodoc-process-docstring", _literal_if_not_rest, priority=600)
    return {"version": "1", "parallel_read_safe": True}
