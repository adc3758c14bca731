"""The package's import graph (``scripts/import_graph.py``): no circles, no upward imports by the
layer table, no module importing another's private name, every module placed in a layer.

The checker itself is tested first on a small package written here, whose graph is known by
construction; then it is run on warpoptics.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import textwrap

import pytest
from _helpers import ROOT

_spec = importlib.util.spec_from_file_location("import_graph", ROOT / "scripts" / "import_graph.py")
ig = importlib.util.module_from_spec(_spec)
sys.modules["import_graph"] = ig  # dataclasses look their module up while the file runs
_spec.loader.exec_module(ig)


TOY_LAYERS = [("low", "errors"), ("mid.*",), ("top", "__init__")]
TOY = {
    "__init__.py": "from . import mid\nimport os\n",
    "errors.py": "",
    # an upward import inside a function still counts, and closes a circle with top
    "low.py": "_secret = 1\n\ndef f():\n    from . import top\n    return top\n",
    # an absolute import under an alias, then a private attribute of it
    "top.py": "import toy.low as L\n\nX = L._secret\n",
    "mid/__init__.py": "from .inner import _hidden, public\n",
    # "from .. import low" is the submodule; the TYPE_CHECKING import of top is exempt
    "mid/inner.py": textwrap.dedent(
        """\
        from typing import TYPE_CHECKING

        from .. import low, errors as e

        if TYPE_CHECKING:
            from ..top import X

        _hidden = public = low
        """
    ),
    "stray.py": "from .errors import *\n",
}


def _write(tmp_path, files: dict[str, str]):
    pkg = tmp_path / "toy"
    for name, text in files.items():
        (pkg / name).parent.mkdir(parents=True, exist_ok=True)
        (pkg / name).write_text(text)
    return pkg


def test_checker_on_a_package_of_known_graph(tmp_path):
    rep = ig.analyze(_write(tmp_path, TOY), layers=TOY_LAYERS)
    assert rep.modules == ["__init__", "errors", "low", "mid", "mid.inner", "stray", "top"]
    edges = {(i.source, i.target) for i in rep.imports}
    assert edges == {
        ("__init__", "mid"),
        ("low", "top"),
        ("top", "low"),
        ("mid", "mid.inner"),
        ("mid.inner", "low"),
        ("mid.inner", "errors"),
        ("stray", "errors"),
    }
    assert rep.circles == [["low", "top", "low"]]
    assert [(i.source, i.target, i.line) for i in rep.upward] == [("low", "top", 4)]
    assert [(p.source, p.target, p.name) for p in rep.private] == [
        ("mid", "mid.inner", "_hidden"),
        ("top", "low", "_secret"),
    ]
    assert rep.unplaced == ["stray"]
    assert rep.layer_of["mid.inner"] == 1 and rep.layer_of["mid"] == 1 and rep.layer_of["__init__"] == 2
    assert not rep.ok


def test_checker_passes_a_clean_package(tmp_path):
    clean = {
        "__init__.py": "from .top import run\n",
        "errors.py": "",
        "low.py": "from .errors import *\n",
        "top.py": "from . import low\nfrom .mid import inner\n\ndef run():\n    return low, inner\n",
        "mid/__init__.py": "",
        "mid/inner.py": "from ..low import *\n",
    }
    rep = ig.analyze(_write(tmp_path, clean), layers=TOY_LAYERS)
    assert rep.ok and not rep.circles and not rep.upward and not rep.private and not rep.unplaced
    assert ("top", "mid.inner") in {(i.source, i.target) for i in rep.imports}


def test_script_exit_code_and_dot(tmp_path):
    """As a command: exit 1 on findings, 0 on a clean package; the DOT file has the edges."""
    pkg = _write(tmp_path, {"__init__.py": "from . import errors\n", "errors.py": "", "device.py": ""})
    dot = tmp_path / "g.dot"
    script = str(ROOT / "scripts" / "import_graph.py")
    p = subprocess.run(
        [sys.executable, script, "--package", str(pkg), "--dot", str(dot)], capture_output=True, text=True
    )
    assert p.returncode == 0, p.stdout + p.stderr
    assert "layer 0: errors, device" in p.stdout and "circles: 0" in p.stdout
    assert '"__init__" -> "errors";' in dot.read_text()
    (pkg / "errors.py").write_text("from . import device\nfrom .device import _x\n")
    p = subprocess.run([sys.executable, script, "--package", str(pkg)], capture_output=True, text=True)
    assert p.returncode == 1 and "errors uses device._x" in p.stdout, p.stdout


@pytest.fixture(scope="module")
def report():
    rep = ig.analyze()
    print(ig.format_report(rep))  # shown with -rA or on failure
    return rep


def test_the_package_is_read(report):
    # a floor, not a count: the checker must have found the package's modules and imports
    assert {"errors", "device", "optics.fresnel", "cli", "__init__"} <= set(report.modules)
    assert ("optics.fresnel", "optics.complex") in {(i.source, i.target) for i in report.imports}


def test_no_import_circles(report):
    assert not report.circles, "\n".join(" -> ".join(c) for c in report.circles)


def test_no_private_names_from_another_module(report):
    assert not report.private, "\n".join(f"{p.file}:{p.line}: {p.target}.{p.name}" for p in report.private)


def test_no_upward_imports(report):
    assert not report.upward, "\n".join(f"{i.file}:{i.line}: {i.source} -> {i.target}" for i in report.upward)


def test_every_module_is_in_the_layer_table(report):
    assert not report.unplaced, report.unplaced
