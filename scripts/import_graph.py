"""The warpoptics module import graph, by layer: circles, upward imports, private-name imports.

    python scripts/import_graph.py                 # print the graph and the findings; exit 1 if any
    python scripts/import_graph.py --dot g.dot     # also write it as Graphviz DOT
    python scripts/import_graph.py --png g.png     # also draw it with matplotlib (docs/layers.png)

A module may import only from its own layer or below (the layers listed below); no module imports
another module's private (``_x``) name; there are no import circles.  Imports are read with ``ast``
without importing anything: relative imports are resolved, ``from . import x`` of a submodule counts
as importing that submodule, imports inside functions count too, imports under
``if TYPE_CHECKING:`` are exempt.  ``from a.b import c`` is an edge to ``a.b.c`` when that is a
module and to ``a.b`` otherwise; the parent packages that Python also runs are not edges (every
submodule would otherwise import its own package ``__init__``).
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import sys
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

# The layer table, bottom to top (module names relative to the package; ``x.*`` is the package
# ``x`` and everything under it; ``__init__`` is the top-level package).  A module may import only
# from its own layer or below.  A new module gets its place here; a module that no entry matches is
# reported as unplaced.
LAYERS: list[tuple[str, ...]] = [
    ("errors", "device", "validate", "atomic", "interrupt"),
    ("spectra", "color", "fields"),
    ("materials.*", "optics.*", "geometry.*"),
    ("film.*",),
    ("stages.*",),
    ("scene.*",),
    ("pipelines.*", "metrics", "grading.*"),
    ("sweep.*",),
    ("cli", "commands.*", "__init__"),
]

PACKAGE = "warpoptics"
ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Import:
    source: str  # importing module, relative name ("optics.fresnel", "__init__")
    target: str  # imported module, relative name
    file: str
    line: int


@dataclass(frozen=True)
class PrivateUse:
    source: str
    target: str
    name: str
    file: str
    line: int


@dataclass
class Report:
    modules: list[str]
    imports: list[Import]
    layer_of: dict[str, int | None]
    circles: list[list[str]] = field(default_factory=list)
    upward: list[Import] = field(default_factory=list)
    private: list[PrivateUse] = field(default_factory=list)

    @property
    def unplaced(self) -> list[str]:
        return [m for m in self.modules if self.layer_of[m] is None]

    @property
    def ok(self) -> bool:
        return not (self.circles or self.upward or self.private or self.unplaced)


def layer_of(module: str, layers=LAYERS) -> int | None:
    """The index of the first layer with an entry matching ``module`` (``x.*`` matches ``x`` too)."""
    for i, entries in enumerate(layers):
        for pattern in entries:
            if module == pattern or fnmatch.fnmatchcase(module, pattern):
                return i
            if pattern.endswith(".*") and module == pattern[:-2]:
                return i
    return None


def _module_names(package_dir: Path) -> dict[str, Path]:
    """Relative module name -> file, for every ``.py`` under ``package_dir``."""
    out = {}
    for f in sorted(package_dir.rglob("*.py")):
        parts = list(f.relative_to(package_dir).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts) if parts else "__init__"] = f
    return out


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _walk_skipping_type_checking(tree: ast.AST):
    """``ast.walk`` that does not enter the body of ``if TYPE_CHECKING:`` (its ``else`` counts)."""
    todo = deque([tree])
    while todo:
        node = todo.popleft()
        yield node
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))


def _absolute(name: str, package: str) -> str | None:
    """``warpoptics.x.y`` -> ``x.y``; ``warpoptics`` -> ``__init__``; another package -> None."""
    if name == package:
        return "__init__"
    if name.startswith(package + "."):
        return name[len(package) + 1 :]
    return None


def _join(module: str, name: str) -> str:
    return name if module == "__init__" else f"{module}.{name}"


def analyze(package_dir: Path | str = ROOT / PACKAGE, layers=LAYERS) -> Report:
    """Read every module of the package at ``package_dir`` and check it against ``layers``."""
    package_dir = Path(package_dir)
    package = package_dir.name
    files = _module_names(package_dir)
    modules = sorted(files)
    imports: list[Import] = []
    private: list[PrivateUse] = []

    for mod, path in files.items():
        is_pkg = path.name == "__init__.py"
        # the package a relative import of level 1 starts from
        here = [] if mod == "__init__" else mod.split(".")
        base = here if is_pkg else here[:-1]
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        rel_file = str(path.relative_to(package_dir.parent))
        aliases: dict[str, str] = {}  # local name bound to one of our modules -> that module

        def add(target: str, node: ast.AST, _mod=mod, _file=rel_file) -> None:
            if target != _mod:
                imports.append(Import(_mod, target, _file, node.lineno))

        for node in _walk_skipping_type_checking(tree):
            if isinstance(node, ast.Import):
                for a in node.names:
                    t = _absolute(a.name, package)
                    if t is None:
                        continue
                    # "import warpoptics.x.y" runs x.y; without "as" it binds only "warpoptics"
                    add(t if t in files else t.rsplit(".", 1)[0], node)
                    if a.asname:
                        aliases[a.asname] = t
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    up = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                    if node.level - 1 > len(base):
                        continue  # beyond the top-level package: not ours
                    parts = up + (node.module.split(".") if node.module else [])
                    src = ".".join(parts) if parts else "__init__"
                else:
                    src = _absolute(node.module or "", package)
                    if src is None:
                        continue
                for a in node.names:
                    sub = _join(src, a.name)
                    if a.name != "*" and sub in files:
                        add(sub, node)  # a submodule
                        aliases[a.asname or a.name] = sub
                        continue
                    add(src, node)
                    if a.name.startswith("_") and not a.name.startswith("__"):
                        private.append(PrivateUse(mod, src, a.name, rel_file, node.lineno))
        # attribute access to a private name of a module imported under a name: "_device._launch"
        for node in _walk_skipping_type_checking(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and _join(aliases[node.value.id], node.attr) not in files
            ):
                private.append(PrivateUse(mod, aliases[node.value.id], node.attr, rel_file, node.lineno))

    imports = sorted(set(imports), key=lambda i: (i.source, i.target, i.line))
    lay = {m: layer_of(m, layers) for m in modules}
    upward = [
        i
        for i in imports
        if lay.get(i.source) is not None and lay.get(i.target) is not None and lay[i.target] > lay[i.source]
    ]
    private = sorted(set(private), key=lambda p: (p.source, p.target, p.name, p.line))
    return Report(modules, imports, lay, _circles(modules, imports), upward, private)


def _circles(modules: list[str], imports: list[Import]) -> list[list[str]]:
    """One shortest cycle per strongly connected component of more than one module (Tarjan)."""
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for i in imports:
        if i.target in graph:
            graph[i.source].add(i.target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    comps: list[list[str]] = []

    def strong(v: str) -> None:  # recursion depth <= number of modules (~100)
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    for m in modules:
        if m not in index:
            strong(m)
    out = []
    for comp in sorted(comps):
        inside = set(comp)
        start = comp[0]
        # breadth-first from start back to start within the component: a shortest cycle
        prev: dict[str, str] = {}
        todo = deque([start])
        found = None
        while todo and found is None:
            v = todo.popleft()
            for w in sorted(graph[v] & inside):
                if w == start:
                    found = v
                    break
                if w not in prev:
                    prev[w] = v
                    todo.append(w)
        path = [found]
        while path[-1] != start:
            path.append(prev[path[-1]])
        out.append([*reversed(path), start])
    return out


def format_report(rep: Report, layers=LAYERS) -> str:
    lines = []
    by_source: dict[str, list[str]] = {}
    for i in rep.imports:
        by_source.setdefault(i.source, [])
        if i.target not in by_source[i.source]:
            by_source[i.source].append(i.target)
    for k, entries in enumerate(layers):
        lines.append(f"layer {k}: {', '.join(entries)}")
        for m in (m for m in rep.modules if rep.layer_of[m] == k):
            targets = ", ".join(by_source.get(m, [])) or "-"
            lines.append(f"  {m} -> {targets}")
    if rep.unplaced:
        lines.append("unplaced (no entry of the layer table matches):")
        for m in rep.unplaced:
            lines.append(f"  {m} -> {', '.join(by_source.get(m, [])) or '-'}")
    lines.append(f"circles: {len(rep.circles)}")
    lines.extend("  " + " -> ".join(c) for c in rep.circles)
    lines.append(f"upward imports: {len(rep.upward)}")
    for i in rep.upward:
        lines.append(
            f"  {i.source} (layer {rep.layer_of[i.source]}) imports {i.target} (layer "
            f"{rep.layer_of[i.target]})  [{i.file}:{i.line}]"
        )
    lines.append(f"private names imported from another module: {len(rep.private)}")
    seen: dict[tuple[str, str, str], list[PrivateUse]] = {}
    for p in rep.private:
        seen.setdefault((p.source, p.target, p.name), []).append(p)
    for (source, target, name), uses in seen.items():
        more = f", +{len(uses) - 1} more" if len(uses) > 1 else ""
        lines.append(f"  {source} uses {target}.{name}  [{uses[0].file}:{uses[0].line}{more}]")
    lines.append(f"unplaced modules: {len(rep.unplaced)}")
    return "\n".join(lines)


def write_dot(rep: Report, path: Path, layers=LAYERS) -> None:
    out = ["digraph warpoptics {", "  rankdir=BT;", "  node [shape=box, fontsize=10];"]
    groups = [(k, f"layer {k}") for k in range(len(layers))] + [(None, "unplaced")]
    for k, label in groups:
        members = [m for m in rep.modules if rep.layer_of[m] == k]
        if not members:
            continue
        out.append(f'  subgraph "cluster_{label}" {{ label="{label}"; rank=same;')
        out.extend(f'    "{m}";' for m in members)
        out.append("  }")
    upward = {(i.source, i.target) for i in rep.upward}
    for s, t in sorted({(i.source, i.target) for i in rep.imports}):
        style = " [color=red, penwidth=2]" if (s, t) in upward else ""
        out.append(f'  "{s}" -> "{t}"{style};')
    out.append("}")
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("\n".join(out) + "\n", encoding="utf-8")
    tmp.replace(path)


def write_png(rep: Report, path: Path, layers=LAYERS, packages: bool = False) -> None:
    """Layers as rows from the bottom; import edges grey, upward ones red.  ``packages``: one box
    per subpackage or top-level module (``optics``, ``stages``, ``color``...), for the README."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if packages:

        def group(m: str) -> str:
            return m.split(".")[0]

        layer_of = {group(m): rep.layer_of[m] for m in rep.modules if rep.layer_of.get(m) is not None}
        edges = {
            (group(i.source), group(i.target))
            for i in rep.imports
            if group(i.source) != group(i.target)
            and group(i.target) in layer_of
            and group(i.source) in layer_of
        }
        up = {e for e in edges if (layer_of[e[1]] or 0) > (layer_of[e[0]] or 0)}
        rep = Report(
            modules=sorted(layer_of),
            imports=[Import(a, b, "", 0) for a, b in sorted(edges)],
            layer_of=layer_of,
            circles=[],
            upward=[Import(a, b, "", 0) for a, b in sorted(up)],
            private=[],
        )
    rows = [[m for m in rep.modules if rep.layer_of[m] == k] for k in range(len(layers))]
    rows.append(rep.unplaced)
    width = max(len(r) for r in rows) or 1
    pos = {}
    for y, row in enumerate(rows):
        for x, m in enumerate(row):
            pos[m] = ((x + 0.5) * width / len(row), y)
    fig, ax = plt.subplots(figsize=(max(8.0, 1.25 * width), 0.9 * len(rows) + 1))
    upward = {(i.source, i.target) for i in rep.upward}
    for s, t in sorted({(i.source, i.target) for i in rep.imports}):
        (x0, y0), (x1, y1) = pos[s], pos[t]
        red = (s, t) in upward
        ax.annotate(
            "",
            xy=(x1, y1),
            xytext=(x0, y0),
            arrowprops={
                "arrowstyle": "->",
                "color": "red" if red else "0.7",
                "lw": 1.2 if red else 0.5,
                "shrinkA": 8,
                "shrinkB": 8,
            },
            zorder=2 if red else 1,
        )
    for m, (x, y) in pos.items():
        ax.text(x, y, m, ha="center", va="center", fontsize=7, zorder=3, bbox={"fc": "white", "ec": "0.3"})
    labels = [f"{k}: {', '.join(e)}" for k, e in enumerate(layers)] + ["unplaced"]
    ax.set_yticks(range(len(rows)), labels, fontsize=7)
    ax.set_xticks([])
    ax.set_xlim(-0.2, width + 0.2)
    ax.set_ylim(-0.6, len(rows) - 0.4)
    ax.set_title("warpoptics imports by layer (red: upward)")
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=80)
    plt.close(fig)
    tmp.replace(path)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--package", type=Path, default=ROOT / PACKAGE, help="the package folder")
    ap.add_argument("--dot", type=Path, help="also write the graph as Graphviz DOT")
    ap.add_argument("--png", type=Path, help="also draw the graph (matplotlib)")
    ap.add_argument("--packages", action="store_true", help="draw one box per subpackage / top-level module")
    args = ap.parse_args(argv)
    rep = analyze(args.package)
    print(format_report(rep))
    if args.dot:
        write_dot(rep, args.dot)
    if args.png:
        write_png(rep, args.png, packages=args.packages)
    return 0 if rep.ok else 1


if __name__ == "__main__":
    sys.exit(main())
