"""Parameter sweeps: a base scene, axes of values addressed by dotted paths, resumable parallel runs.

A sweep renders one job per combination of axis values and measures each image with the
metrics of :mod:`warpoptics.metrics`.  It is defined in TOML (``Sweep.load``) or in Python
(``Sweep(...)``)::

    name = "pavilion"
    description = "Light return and fire of a round brilliant against its pavilion angle"
    scene = "round_brilliant_faceup.toml"  # the base scene, relative to this file
    mode = "product"                       # how axes combine: "product" or "zip"
    label = "{pavilion:.2f} deg"           # optional: a job's label (str.format of the variables;
                                           # an axis with labels shows its label)

    [set]                                  # fixed overrides of every job (dotted paths)
    "render.wavelengths" = 16

    [[axis]]
    name = "pavilion"                      # a variable name for labels and expressions
    path = "object.0.pavilion_angle"       # optional: the scene value it sets
    values = [40.0, 40.75, 41.5]           # or linspace = [38.0, 44.0, 13]
    # group = "g"  axes of the same group are zipped together, groups combine as a product
    # labels = ["a", "b", "c"]  display labels (e.g. for inline-table values)

    [expr]                                 # per-job values computed from the variables
    s = "size_mm / 6.5"                    # a key without a dot: a variable for later expressions
    "camera.position" = "[0.0, -22.0 * s, 30.0 * s]"

    [[view]]                               # renders per job (default: one view, metrics ["color"])
    name = "dome"
    set = { "light.0.map" = "dome" }
    expr = { }
    metrics = ["color", "light_return"]    # color, light_return, fire, scintillation
    tilts = [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]   # scintillation: stone tilts in degrees
    save = true                            # write this view's EXR + PNG

    [compare]                              # paired ΔE between jobs that differ only in one axis
    axis = "kk"
    reference = false
    scale = 10.0                           # ΔE at the top of the difference images' colour map

Dotted paths are those of ``Scene.with_overrides`` (``object.0.diameter``, ``render.spp``,
``camera.position``, ``light.0.map``); paths below ``object.N.material`` turn a material name into
an inline table first (``object.0.material.kramers_kronig = true`` on ``material = "spinel"``
means ``{ base = "spinel", kramers_kronig = true }``), and reach into arrays of tables
(``object.0.material.bands.0.peak_alpha_per_mm``).  Note that ``object.N.absorption_scale``
multiplies only the Bouguer–Lambert alpha of the transport; the material's k (Fresnel, and
the Kramers–Kronig Δn) follow the material's own absorption.  Relative ``light.N.map`` files
are resolved against the file that names them (the sweep file, or the base scene).

Expressions are Python syntax restricted to numbers, strings, booleans, lists, dicts, arithmetic,
comparisons, ``a if c else b`` and the functions abs, min, max, round, float, int, bool, sqrt,
exp, log, log10, sin, cos, tan, asin, acos, atan, atan2, radians, degrees, and pi, e.

Execution (:class:`SweepRunner`): in this process (``workers=1``), in a process or thread pool,
or on a Dask cluster (``scheduler="tcp://host:port"`` or ``dask_local=N``) with the same job
function (:func:`run_job`).  Only the runner writes the output directory: each finished job's
EXR + PNG are written atomically, then its row is appended to ``results.csv`` (flushed and
fsynced), so a killed run loses at most the jobs in flight; a rerun with ``resume=True`` skips
the jobs whose rows are there (a torn last line is dropped).  Renders are deterministic (seeded
per pixel, independent of threads and tiling), so the table does not depend on the backend.
At the end: ``results.csv`` in job order, ``pairs.csv`` and difference images (with
``[compare]``), ``contact_sheet.png``, ``plots/<metric>_vs_<axis>.png`` and ``summary.md``.
"""

from __future__ import annotations

import ast
import contextlib
import copy
import csv
import difflib
import hashlib
import io
import itertools
import json
import math
import os
import re
import sys
import time
import tomllib
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError

__all__ = [
    "Axis",
    "View",
    "Compare",
    "Sweep",
    "Job",
    "SweepRunner",
    "SweepResult",
    "METRICS",
    "run_job",
    "evaluate_expression",
    "apply_overrides",
    "read_results",
]

# metric name -> columns it adds to results.csv (per view)
METRICS: dict[str, tuple[str, ...]] = {
    "color": ("X", "Y", "Z", "L", "a", "b", "C", "h", "coverage"),
    "light_return": ("light_return",),
    "fire": ("fire",),
    "fire_excess": ("fire_nondispersive", "fire_excess"),
    "scintillation": ("scintillation",),
}
_PLOTTED_COLOR_COLUMNS = ("L", "C", "h")
_PAIR_COLUMNS = ("dE_mean", "dE_p95", "dE_max", "dE_mean_color")

# ----------------------------------------------------------------------------------------------
# Expressions
# ----------------------------------------------------------------------------------------------

_FUNCTIONS: dict[str, Callable] = {
    "abs": abs,
    "min": min,
    "max": max,
    "round": round,
    "float": float,
    "int": int,
    "bool": bool,
    "sqrt": math.sqrt,
    "exp": math.exp,
    "log": math.log,
    "log10": math.log10,
    "sin": math.sin,
    "cos": math.cos,
    "tan": math.tan,
    "asin": math.asin,
    "acos": math.acos,
    "atan": math.atan,
    "atan2": math.atan2,
    "radians": math.radians,
    "degrees": math.degrees,
}
_CONSTANTS = {"pi": math.pi, "e": math.e, "true": True, "false": False}
_BINOPS = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.FloorDiv: lambda a, b: a // b,
    ast.Mod: lambda a, b: a % b,
    ast.Pow: lambda a, b: a**b,
}
_CMPOPS = {
    ast.Eq: lambda a, b: a == b,
    ast.NotEq: lambda a, b: a != b,
    ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b,
    ast.Gt: lambda a, b: a > b,
    ast.GtE: lambda a, b: a >= b,
}


def evaluate_expression(
    text: str, variables: dict[str, Any], *, file: str | None = None, field_name: str | None = None
) -> Any:
    """Evaluate a sweep expression (restricted Python syntax, see the module docstring)."""

    def fail(msg: str):
        raise InputError(msg, file=file, field=field_name, value=text)

    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        fail(f"not a valid expression ({exc.msg})")

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str, bool)):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in variables:
                return variables[node.id]
            if node.id in _CONSTANTS:
                return _CONSTANTS[node.id]
            hint = difflib.get_close_matches(node.id, list(variables) + list(_CONSTANTS), n=1)
            fail(
                f"unknown name {node.id!r}"
                + (f"; did you mean {hint[0]!r}?" if hint else "")
                + f" (variables: {', '.join(variables) or 'none'})"
            )
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            return _BINOPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp):
            v = ev(node.operand)
            if isinstance(node.op, ast.USub):
                return -v
            if isinstance(node.op, ast.UAdd):
                return +v
            if isinstance(node.op, ast.Not):
                return not v
        if isinstance(node, ast.BoolOp):
            vals = [ev(v) for v in node.values]
            return all(vals) if isinstance(node.op, ast.And) else any(vals)
        if isinstance(node, ast.Compare):
            left = ev(node.left)
            for op, right_node in zip(node.ops, node.comparators, strict=True):
                if type(op) not in _CMPOPS:
                    fail("unsupported comparison")
                right = ev(right_node)
                if not _CMPOPS[type(op)](left, right):
                    return False
                left = right
            return True
        if isinstance(node, ast.IfExp):
            return ev(node.body) if ev(node.test) else ev(node.orelse)
        if isinstance(node, (ast.List, ast.Tuple)):
            return [ev(v) for v in node.elts]
        if isinstance(node, ast.Dict):
            if any(k is None for k in node.keys):
                fail("** in a table is not supported")
            return {ev(k): ev(v) for k, v in zip(node.keys, node.values, strict=True)}
        if isinstance(node, ast.Subscript):
            return ev(node.value)[ev(node.slice)]
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
            fn = _FUNCTIONS.get(node.func.id)
            if fn is None:
                fail(f"unknown function {node.func.id!r} (allowed: {', '.join(_FUNCTIONS)})")
            return fn(*[ev(a) for a in node.args])
        fail(f"unsupported syntax: {type(node).__name__}")

    try:
        return ev(tree)
    except InputError:
        raise
    except (ArithmeticError, TypeError, ValueError, IndexError, KeyError) as exc:
        fail(f"cannot evaluate ({type(exc).__name__}: {exc})")


# ----------------------------------------------------------------------------------------------
# Definitions
# ----------------------------------------------------------------------------------------------

_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _check_name(name, *, file, field_name) -> str:
    if not isinstance(name, str) or not _NAME_RE.match(name) or name in _FUNCTIONS or name in _CONSTANTS:
        raise InputError(
            "must be an identifier (letters, digits, _) that is not a function or constant name",
            file=file,
            field=field_name,
            value=name,
        )
    return name


@dataclass(frozen=True)
class Axis:
    """One sweep axis: a variable ``name`` taking ``values``; ``path`` (dotted) is the scene value
    it sets (None: a variable used only by expressions and labels).  Axes with the same
    ``group`` are zipped together; ``labels`` are display strings for the values."""

    name: str
    values: tuple
    path: str | None = None
    group: str | None = None
    labels: tuple[str, ...] | None = None

    def __post_init__(self):
        _check_name(self.name, file=None, field_name="axis.name")
        object.__setattr__(self, "values", tuple(self.values))
        if not self.values:
            raise InputError("an axis needs at least one value", field=f"axis.{self.name}.values")
        if self.labels is not None:
            object.__setattr__(self, "labels", tuple(str(v) for v in self.labels))
            if len(self.labels) != len(self.values):
                raise InputError(
                    "needs one label per value",
                    field=f"axis.{self.name}.labels",
                    value=len(self.labels),
                    allowed=str(len(self.values)),
                )

    def label_of(self, i: int) -> str:
        return self.labels[i] if self.labels is not None else _format_value(self.values[i])


@dataclass(frozen=True)
class View:
    """A render of each job: extra overrides (``set`` literal values, ``expr`` expressions) on
    top of the job's, and the metrics measured on it (keys of :data:`METRICS`).  ``tilts``:
    rotations (degrees about x, y, z, added to ``object.<tilt_object>.rotation``) rendered for
    ``scintillation``.  ``white_y``: the lighting's white luminance for ``light_return``.
    ``fire_reference`` / ``fire_min_saturation``: see :func:`warpoptics.metrics.fire`."""

    name: str = "main"
    set: dict = field(default_factory=dict)
    expr: dict = field(default_factory=dict)
    metrics: tuple[str, ...] = ("color",)
    tilts: tuple[tuple[float, float, float], ...] = ((2.0, 0.0, 0.0), (0.0, 2.0, 0.0))
    tilt_object: int = 0
    white_y: float = 1.0
    fire_reference: str = "white"
    fire_min_saturation: float = 0.0
    save: bool = True

    def __post_init__(self):
        _check_name(self.name, file=None, field_name="view.name")
        object.__setattr__(self, "metrics", tuple(self.metrics))
        for m in self.metrics:
            if m not in METRICS:
                raise InputError(
                    "unknown metric", field=f"view.{self.name}.metrics", value=m, allowed=", ".join(METRICS)
                )
        object.__setattr__(self, "tilts", tuple(tuple(float(c) for c in t) for t in self.tilts))
        if any(len(t) != 3 for t in self.tilts):
            raise InputError("each tilt is [x, y, z] in degrees", field=f"view.{self.name}.tilts")
        if "scintillation" in self.metrics and not self.tilts:
            raise InputError("scintillation needs tilts", field=f"view.{self.name}.tilts")
        if self.fire_reference not in ("white", "mean"):
            raise InputError(
                "unknown value",
                field=f"view.{self.name}.fire_reference",
                value=self.fire_reference,
                allowed="white, mean",
            )


@dataclass(frozen=True)
class Compare:
    """Pair each job whose ``axis`` value differs from ``reference`` with the job that has the
    ``reference`` value and the same other values; ΔE maps use ``scale`` as full scale."""

    axis: str
    reference: Any
    scale: float = 10.0


@dataclass(frozen=True)
class Job:
    """A resolved job: its variables, the dotted overrides of its base render and of each view."""

    index: int
    key: str
    label: str
    values: dict  # axis name -> value
    labels: dict  # axis name -> display string
    overrides: dict  # dotted path -> value (fixed set + axes + expressions)
    views: tuple  # ((view name, overrides), ...)


def _format_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (int, str)):
        return str(v)
    return json.dumps(v, sort_keys=True)


def _linspace(spec, *, file, field_name) -> list[float]:
    if (
        not isinstance(spec, list)
        or len(spec) != 3
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in spec)
        or int(spec[2]) != spec[2]
        or spec[2] < 1
    ):
        raise InputError("must be [start, stop, count]", file=file, field=field_name, value=spec)
    n = int(spec[2])
    return [float(v) for v in np.round(np.linspace(spec[0], spec[1], n), 12)]


_TOP_KEYS = {
    "name",
    "description",
    "scene",
    "mode",
    "label",
    "metrics",
    "set",
    "expr",
    "axis",
    "view",
    "compare",
}
_AXIS_KEYS = {"name", "path", "values", "linspace", "group", "labels"}
_VIEW_KEYS = {
    "name",
    "set",
    "expr",
    "metrics",
    "tilts",
    "tilt_object",
    "white_y",
    "fire_reference",
    "fire_min_saturation",
    "save",
}
_COMPARE_KEYS = {"axis", "reference", "scale"}


def _check_keys(table, allowed, *, file, prefix):
    if not isinstance(table, dict):
        raise InputError("must be a table", file=file, field=prefix.rstrip("."))
    for k in table:
        if k not in allowed:
            close = difflib.get_close_matches(k, list(allowed), n=1, cutoff=0.6)
            raise InputError(
                "unknown key" + (f"; did you mean {close[0]!r}?" if close else ""),
                file=file,
                field=f"{prefix}{k}",
                allowed=", ".join(sorted(allowed)),
            )


@dataclass(frozen=True)
class Sweep:
    """A sweep definition (see the module docstring).  ``scene``: a path (relative to
    ``base_dir``) or a :class:`~warpoptics.scene.Scene`.  ``expr`` values are expression strings
    or, from Python, callables of the variables' dict."""

    scene: Any
    axes: tuple[Axis, ...]
    mode: str = "product"
    set: dict = field(default_factory=dict)
    expr: dict = field(default_factory=dict)
    views: tuple[View, ...] = (View(),)
    compare: Compare | None = None
    name: str = "sweep"
    description: str = ""
    label: str | None = None
    base_dir: Path = field(default_factory=Path.cwd)
    source: str | None = None

    def __post_init__(self):
        file = self.source
        object.__setattr__(self, "axes", tuple(self.axes))
        object.__setattr__(self, "views", tuple(self.views) or (View(),))
        object.__setattr__(self, "base_dir", Path(self.base_dir))
        if self.mode not in ("product", "zip"):
            raise InputError("unknown mode", file=file, field="mode", value=self.mode, allowed="product, zip")
        if not self.axes:
            raise InputError("a sweep needs at least one [[axis]]", file=file, field="axis")
        names = [a.name for a in self.axes]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise InputError("axis names must be unique", file=file, field="axis.name", value=sorted(dup))
        vnames = [v.name for v in self.views]
        if len(set(vnames)) != len(vnames):
            raise InputError("view names must be unique", file=file, field="view.name", value=vnames)
        for k in self.expr:
            if "." not in k:
                _check_name(k, file=file, field_name=f"expr.{k}")
                if k in names:
                    raise InputError(
                        "an expression variable cannot reuse an axis name", file=file, field=f"expr.{k}"
                    )
        if self.compare is not None:
            ax = next((a for a in self.axes if a.name == self.compare.axis), None)
            if ax is None:
                raise InputError(
                    "unknown axis",
                    file=file,
                    field="compare.axis",
                    value=self.compare.axis,
                    allowed=", ".join(names),
                )
            if self.compare.reference not in ax.values:
                raise InputError(
                    "the reference must be one of the axis values",
                    file=file,
                    field="compare.reference",
                    value=self.compare.reference,
                    allowed=", ".join(_format_value(v) for v in ax.values),
                )
            if not self.compare.scale > 0:
                raise InputError("must be > 0", file=file, field="compare.scale", value=self.compare.scale)
        groups = self._groups()
        for g in groups:
            lens = {len(a.values) for a in g}
            if len(lens) > 1:
                raise InputError(
                    "zipped axes must have the same number of values",
                    file=file,
                    field="axis",
                    value={a.name: len(a.values) for a in g},
                )

    # -- loading -----------------------------------------------------------------------------

    @classmethod
    def load(cls, path: str | Path, *, extra_set: dict | None = None) -> Sweep:
        """Read a sweep TOML file; ``extra_set`` (dotted path -> value) is added to ``[set]``."""
        p = Path(path)
        file = str(p)
        if not p.is_file():
            raise InputError("sweep file not found", file=file)
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML ({exc})", file=file) from None
        return cls.from_dict(data, base_dir=p.parent, source=file, extra_set=extra_set)

    @classmethod
    def from_dict(
        cls,
        data: dict,
        *,
        base_dir: str | Path | None = None,
        source: str | None = None,
        extra_set: dict | None = None,
    ) -> Sweep:
        file = source or "<sweep>"
        _check_keys(data, _TOP_KEYS, file=file, prefix="")
        if "scene" not in data or not isinstance(data["scene"], str):
            raise InputError('missing the base scene: scene = "file.toml"', file=file, field="scene")
        axes_t = data.get("axis", [])
        if not isinstance(axes_t, list):
            raise InputError("must be an array of tables [[axis]]", file=file, field="axis")
        axes = []
        for i, t in enumerate(axes_t):
            pre = f"axis.{i}."
            _check_keys(t, _AXIS_KEYS, file=file, prefix=pre)
            if "name" not in t:
                raise InputError("missing key", file=file, field=pre + "name")
            _check_name(t["name"], file=file, field_name=pre + "name")
            if ("values" in t) == ("linspace" in t):
                raise InputError(
                    "give exactly one of values = [...] or linspace = [start, stop, count]",
                    file=file,
                    field=pre + "values",
                )
            values = (
                t["values"]
                if "values" in t
                else _linspace(t["linspace"], file=file, field_name=pre + "linspace")
            )
            if not isinstance(values, list) or not values:
                raise InputError("must be a non-empty list", file=file, field=pre + "values", value=values)
            path = t.get("path")
            if path is not None and (not isinstance(path, str) or "." not in path):
                raise InputError(
                    "must be a dotted path like object.0.diameter", file=file, field=pre + "path", value=path
                )
            labels = t.get("labels")
            if labels is not None and (not isinstance(labels, list) or len(labels) != len(values)):
                raise InputError("needs one label per value", file=file, field=pre + "labels", value=labels)
            group = t.get("group")
            if group is not None and not isinstance(group, str):
                raise InputError("must be a string", file=file, field=pre + "group", value=group)
            axes.append(
                Axis(
                    t["name"], tuple(values), path=path, group=group, labels=tuple(labels) if labels else None
                )
            )
        fixed = dict(data.get("set", {}))
        _check_keys(fixed, set(fixed), file=file, prefix="set.")
        for k in fixed:
            if "." not in k:
                raise InputError("must be a dotted path like render.spp", file=file, field=f"set.{k}")
        if extra_set:
            fixed.update(extra_set)
        expr = dict(data.get("expr", {}))
        _check_keys(expr, set(expr), file=file, prefix="expr.")
        views = []
        metrics = data.get("metrics", ["color"])
        views_t = data.get("view", [])
        if not isinstance(views_t, list):
            raise InputError("must be an array of tables [[view]]", file=file, field="view")
        if views_t and "metrics" in data:
            raise InputError("with [[view]] tables, give metrics in each view", file=file, field="metrics")
        if not views_t:
            views_t = [{"name": "main", "metrics": metrics}]
        for i, t in enumerate(views_t):
            pre = f"view.{i}."
            _check_keys(t, _VIEW_KEYS, file=file, prefix=pre)
            kw = dict(t)
            name = kw.pop("name", "main" if len(views_t) == 1 else f"view{i}")
            _check_name(name, file=file, field_name=pre + "name")
            for k in ("set", "expr"):
                if k in kw and not isinstance(kw[k], dict):
                    raise InputError("must be a table", file=file, field=pre + k)
            if "metrics" in kw:
                ms = kw["metrics"]
                if not isinstance(ms, list) or not all(isinstance(m, str) for m in ms):
                    raise InputError(
                        "must be a list of metric names",
                        file=file,
                        field=pre + "metrics",
                        value=ms,
                        allowed=", ".join(METRICS),
                    )
                for m in ms:
                    if m not in METRICS:
                        close = difflib.get_close_matches(m, list(METRICS), n=1)
                        raise InputError(
                            "unknown metric" + (f"; did you mean {close[0]!r}?" if close else ""),
                            file=file,
                            field=pre + "metrics",
                            value=m,
                            allowed=", ".join(METRICS),
                        )
            if "tilts" in kw:
                tl = kw["tilts"]
                if not isinstance(tl, list) or not all(isinstance(x, list) and len(x) == 3 for x in tl):
                    raise InputError(
                        "must be a list of [x, y, z] rotations in degrees",
                        file=file,
                        field=pre + "tilts",
                        value=tl,
                    )
            try:
                views.append(View(name=name, **kw))
            except TypeError as exc:
                raise InputError(f"invalid view ({exc})", file=file, field=pre.rstrip(".")) from None
        compare = None
        if "compare" in data:
            c = data["compare"]
            _check_keys(c, _COMPARE_KEYS, file=file, prefix="compare.")
            if "axis" not in c or "reference" not in c:
                raise InputError('needs axis = "name" and reference = value', file=file, field="compare")
            compare = Compare(c["axis"], c["reference"], float(c.get("scale", 10.0)))
        label = data.get("label")
        if label is not None and not isinstance(label, str):
            raise InputError("must be a format string", file=file, field="label", value=label)
        return cls(
            scene=data["scene"],
            axes=tuple(axes),
            mode=data.get("mode", "product"),
            set=fixed,
            expr=expr,
            views=tuple(views),
            compare=compare,
            name=str(data.get("name", Path(file).stem)),
            description=str(data.get("description", "")),
            label=label,
            base_dir=Path(base_dir) if base_dir is not None else Path.cwd(),
            source=source,
        )

    # -- jobs --------------------------------------------------------------------------------

    def scene_source(self) -> tuple[dict, str | None, str]:
        """(raw scene data, scene path or None, digest of the scene's content)."""
        from .scene import Scene

        if isinstance(self.scene, Scene):
            data = copy.deepcopy(self.scene.data)
            digest = hashlib.sha1(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()
            return data, self.scene.path, digest
        p = Path(self.scene)
        if not p.is_absolute():
            p = self.base_dir / p
        if not p.is_file():
            raise InputError(
                "base scene file not found", file=self.source, field="scene", value=str(self.scene)
            )
        text = p.read_text(encoding="utf-8")
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML ({exc})", file=str(p)) from None
        return data, str(p), hashlib.sha1(text.encode()).hexdigest()

    def _groups(self) -> list[list[Axis]]:
        if self.mode == "zip":
            return [list(self.axes)]
        groups: dict[str, list[Axis]] = {}
        order: list[list[Axis]] = []
        for a in self.axes:
            if a.group is None:
                order.append([a])
            elif a.group in groups:
                groups[a.group].append(a)
            else:
                groups[a.group] = [a]
                order.append(groups[a.group])
        return order

    def combinations(self) -> list[dict[str, int]]:
        """Index of each axis's value, per job, in job order (first axis outermost)."""
        groups = self._groups()
        out = []
        for combo in itertools.product(*[range(len(g[0].values)) for g in groups]):
            idx = {}
            for g, i in zip(groups, combo, strict=True):
                for a in g:
                    idx[a.name] = i
            out.append(idx)
        return out

    def _eval_table(self, table: dict, variables: dict, overrides: dict, *, prefix: str) -> None:
        for k, v in table.items():
            if callable(v):
                try:
                    value = v(dict(variables))
                except Exception as exc:  # a user's callable: report which one failed
                    raise InputError(
                        f"expression failed ({type(exc).__name__}: {exc})",
                        file=self.source,
                        field=f"{prefix}{k}",
                    ) from None
            elif isinstance(v, str):
                value = evaluate_expression(v, variables, file=self.source, field_name=f"{prefix}{k}")
            else:
                value = v
            if isinstance(value, float) and not math.isfinite(value):
                raise InputError(
                    "evaluates to a non-finite number",
                    file=self.source,
                    field=f"{prefix}{k}",
                    value=v if isinstance(v, str) else None,
                )
            if "." in k:
                overrides[k] = value
            else:
                variables[k] = value

    def jobs(self) -> list[Job]:
        """All jobs, resolved: overrides are plain data (picklable, hashed into each job's key)."""
        data, _path, digest = self.scene_source()
        jobs = []
        for index, idx in enumerate(self.combinations()):
            values = {a.name: a.values[idx[a.name]] for a in self.axes}
            labels = {a.name: a.label_of(idx[a.name]) for a in self.axes}
            variables = dict(values)
            overrides = dict(self.set)
            for a in self.axes:
                if a.path is not None:
                    overrides[a.path] = values[a.name]
            self._eval_table(self.expr, variables, overrides, prefix="expr.")
            views = []
            for v in self.views:
                vo: dict = dict(v.set)
                vvars = dict(variables)
                self._eval_table(v.expr, vvars, vo, prefix=f"view.{v.name}.expr.")
                views.append((v.name, vo))
            if self.label:
                try:
                    # axes with display labels show them; other variables their values
                    shown = {
                        **variables,
                        **{a.name: labels[a.name] for a in self.axes if a.labels is not None},
                    }
                    label = self.label.format(**shown)
                except (KeyError, ValueError, IndexError) as exc:
                    raise InputError(
                        f"cannot format the label ({exc})", file=self.source, field="label", value=self.label
                    ) from None
            else:
                label = (
                    ", ".join(f"{a.name}={labels[a.name]}" for a in self.axes if len(a.values) > 1) or "job"
                )
            blob = json.dumps(
                {
                    "scene": digest,
                    "overrides": overrides,
                    "views": views,
                    "view_settings": [_view_settings(v) for v in self.views],
                },
                sort_keys=True,
                default=repr,
            )
            key = f"{index:04d}_{hashlib.sha1(blob.encode()).hexdigest()[:10]}"
            jobs.append(
                Job(
                    index=index,
                    key=key,
                    label=label,
                    values=values,
                    labels=labels,
                    overrides=overrides,
                    views=tuple(views),
                )
            )
        return jobs

    def columns(self) -> list[str]:
        """Metric columns of results.csv (``<view>_<column>`` when there are several views)."""
        cols = []
        for v in self.views:
            for m in v.metrics:
                for c in METRICS[m]:
                    cols.append(c if len(self.views) == 1 else f"{v.name}_{c}")
        return cols

    def validate(self, jobs: Sequence[Job] | None = None) -> None:
        """Build every job's scene (not its materials or geometry): bad paths or values fail here,
        before any rendering."""
        data, path, _ = self.scene_source()
        for job in jobs if jobs is not None else self.jobs():
            for _name, vo in job.views:
                scene_for(data, path, {**job.overrides, **vo}, self.base_dir)


def _view_settings(v: View) -> dict:
    return {
        "name": v.name,
        "metrics": list(v.metrics),
        "tilts": [list(t) for t in v.tilts],
        "tilt_object": v.tilt_object,
        "white_y": v.white_y,
        "fire_reference": v.fire_reference,
        "fire_min_saturation": v.fire_min_saturation,
        "save": v.save,
    }


# ----------------------------------------------------------------------------------------------
# The job function (runs in this process, a pool worker or a Dask worker)
# ----------------------------------------------------------------------------------------------

_MAP_RE = re.compile(r"^light\.\d+\.map$")
_MATERIAL_RE = re.compile(r"^(object\.\d+\.material)\.")


def _resolve_map(value, base: Path | None):
    if isinstance(value, str) and Path(value).suffix and not Path(value).is_absolute() and base is not None:
        return str((base / value).resolve())
    return value


def apply_overrides(data: dict, overrides: dict, *, file: str = "<scene>") -> dict:
    """A deep copy of raw scene ``data`` with dotted ``overrides`` set (see the module
    docstring: a material name becomes ``{ base = name }`` when a path reaches below it)."""
    from .scene import set_dotted

    out = copy.deepcopy(data)
    for dotted, value in overrides.items():
        m = _MATERIAL_RE.match(dotted)
        if m:
            parts = m.group(1).split(".")
            objs = out.get("object")
            if isinstance(objs, list) and parts[1].isdigit() and int(parts[1]) < len(objs):
                ob = objs[int(parts[1])]
                mat = ob.get("material", "diamond") if isinstance(ob, dict) else None
                if isinstance(mat, str):
                    ob["material"] = {"base": mat}
        set_dotted(out, dotted, copy.deepcopy(value), file=file)
    return out


def scene_for(data: dict, scene_path: str | None, overrides: dict, sweep_dir: Path | str | None):
    """The :class:`~warpoptics.scene.Scene` of ``data`` with ``overrides``; relative light-map
    files resolve against the base scene's folder (its own) or ``sweep_dir`` (overrides)."""
    from .scene import Scene

    base_dir = Path(scene_path).parent if scene_path else None
    d = copy.deepcopy(data)
    for light in d.get("light", []) if isinstance(d.get("light"), list) else []:
        if isinstance(light, dict) and "map" in light:
            light["map"] = _resolve_map(light["map"], base_dir)
    ov = {
        k: (_resolve_map(v, Path(sweep_dir)) if _MAP_RE.match(k) and sweep_dir is not None else v)
        for k, v in overrides.items()
    }
    return Scene.from_dict(apply_overrides(d, ov, file=scene_path or "<scene>"), path=scene_path)


def nondispersive(scene):
    """``scene`` with every object's material replaced by a dispersion-free one: a constant index
    equal to the material's (ordinary) n at 589.3 nm, no absorption.  Rendered with the same
    per-pixel camera samples (wavelengths, jitter), it is the baseline of ``fire_excess``:
    colour that sampling alone puts on small bright features cancels in the difference."""
    from .materials import material_from_spec

    ov = {}
    for i, ob in enumerate(scene.objects):
        mat = material_from_spec(ob.material)
        n_d = float(np.real(np.asarray(mat.n(np.array([589.3])))).ravel()[0])
        ov[f"object.{i}.material"] = {"cauchy": [n_d]}
    return scene.with_overrides(ov)


def _render(scene, device, threads):
    from .render import Renderer

    return Renderer(scene, device=device).run(threads=threads)


def run_job(payload: dict) -> dict:
    """Render and measure one job.  ``payload``: ``scene_data``, ``scene_path``, ``sweep_dir``,
    ``job`` (a :class:`Job` as a dict), ``views`` (view settings), ``device``, ``threads``.
    Returns ``{"key", "index", "metrics": {column: value}, "images": {view: arrays}, "rays",
    "seconds"}``; writes nothing (the runner owns the output folder)."""
    from . import metrics as wm

    t0 = time.perf_counter()
    job = payload["job"]
    settings = {v["name"]: v for v in payload["views"]}
    several = len(payload["views"]) > 1
    data, path, sweep_dir = payload["scene_data"], payload["scene_path"], payload["sweep_dir"]
    device, threads = payload.get("device"), payload.get("threads")
    out_metrics: dict[str, float] = {}
    images: dict[str, dict] = {}
    rays = 0
    for vname, vo in job["views"]:
        vs = settings[vname]
        scene = scene_for(data, path, {**job["overrides"], **vo}, sweep_dir)
        img = _render(scene, device, threads)
        rays += int(img.stats.get("rays", 0))
        vals: dict[str, float] = {}
        for m in vs["metrics"]:
            if m == "color":
                vals.update(wm.mean_color(img.xyz, img.alpha))
            elif m == "light_return":
                vals["light_return"] = wm.light_return(img.xyz, img.alpha, white_y=vs["white_y"])
            elif m in ("fire", "fire_excess"):
                kw = {"reference": vs["fire_reference"], "min_saturation": vs["fire_min_saturation"]}
                if "fire" not in vals:
                    vals["fire"] = wm.fire(img.xyz, img.alpha, **kw)
                if m == "fire_excess":
                    flat = _render(nondispersive(scene), device, threads)
                    rays += int(flat.stats.get("rays", 0))
                    vals["fire_nondispersive"] = wm.fire(flat.xyz, flat.alpha, **kw)
                    vals["fire_excess"] = vals["fire"] - vals["fire_nondispersive"]
            elif m == "scintillation":
                i = int(vs["tilt_object"])
                if not 0 <= i < len(scene.objects):
                    raise InputError("no such object", field=f"view.{vname}.tilt_object", value=i)
                rot = np.asarray(scene.objects[i].rotation, dtype=np.float64)
                tilted = []
                for t in vs["tilts"]:
                    st = scene.with_overrides(
                        {f"object.{i}.rotation": [float(c) for c in rot + np.asarray(t)]}
                    )
                    ti = _render(st, device, threads)
                    rays += int(ti.stats.get("rays", 0))
                    tilted.append((ti.xyz, ti.alpha))
                vals["scintillation"] = wm.scintillation(img.xyz, img.alpha, tilted)
        for m in vs["metrics"]:
            for c in METRICS[m]:
                out_metrics[f"{vname}_{c}" if several else c] = float(vals[c])
        if vs["save"]:
            images[vname] = {
                "xyz": img.xyz.astype(np.float32),
                "alpha": img.alpha.astype(np.float32),
                "stokes": img.stokes.astype(np.float32),
                "exposure": img.exposure,
                "tone": img.tone,
            }
    return {
        "key": job["key"],
        "index": job["index"],
        "metrics": out_metrics,
        "images": images,
        "rays": rays,
        "seconds": time.perf_counter() - t0,
    }


# ----------------------------------------------------------------------------------------------
# results.csv: append-only rows, tolerant of a torn last line
# ----------------------------------------------------------------------------------------------


def _csv_line(values: Sequence) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(values)
    return buf.getvalue()


def read_results(path: str | Path, *, repair: bool = False) -> tuple[list[str] | None, list[dict]]:
    """(header, rows) of a results.csv.  A last line without its newline (a write cut short by a
    kill) or with the wrong number of fields is ignored; ``repair=True`` also truncates the file
    to its last complete line, so that appends start on a fresh line."""
    p = Path(path)
    if not p.is_file():
        return None, []
    raw = p.read_bytes()
    end = raw.rfind(b"\n") + 1  # 0 when there is no complete line
    if repair and end != len(raw):
        with open(p, "r+b") as f:
            f.truncate(end)
            f.flush()
            os.fsync(f.fileno())
    text = raw[:end].decode("utf-8", errors="replace")
    reader = csv.reader(io.StringIO(text))
    lines = list(reader)
    if not lines:
        return None, []
    header, rows = lines[0], []
    for ln in lines[1:]:
        if len(ln) == len(header):
            rows.append(dict(zip(header, ln, strict=True)))
    return header, rows


def _append_line(path: Path, line: str) -> None:
    with open(path, "a", encoding="utf-8") as f:  # not-a-replace: append-only journal, fsync per row
        f.write(line)
        f.flush()
        os.fsync(f.fileno())


def _write_text_atomic(path: Path, text: str) -> None:
    from .image import atomic_path

    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())


# ----------------------------------------------------------------------------------------------
# Backends: each yields job results as they finish
# ----------------------------------------------------------------------------------------------


def _local_results(payloads) -> Iterator[dict]:
    for p in payloads:
        yield run_job(p)


def _pool_results(payloads, workers: int, kind: str) -> Iterator[dict]:
    import concurrent.futures as cf
    import multiprocessing

    if kind == "process":
        ex = cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
    else:
        ex = cf.ThreadPoolExecutor(max_workers=workers, thread_name_prefix="sweep")
    futures = []
    try:
        if kind == "thread" and payloads:
            # Warp modules load on this (the main) thread: the first job runs here
            yield run_job(payloads[0])
            payloads = payloads[1:]
        futures = [ex.submit(run_job, p) for p in payloads]
        for f in cf.as_completed(futures):
            yield f.result()
    finally:
        for f in futures:
            f.cancel()
        ex.shutdown(wait=True, cancel_futures=True)


def _dask_results(payloads, *, scheduler: str | None, dask_local: int | None) -> Iterator[dict]:
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError(
            "Dask is not installed: pip install 'warpoptics[distributed]' (dask[distributed])",
            field="--scheduler" if scheduler else "--dask-local",
        ) from None
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(
            n_workers=int(dask_local),
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=40,
        )
        client = Client(cluster)
    try:
        futures = [
            client.submit(run_job, p, key=f"warpoptics-job-{p['job']['key']}-{i}", pure=False)
            for i, p in enumerate(payloads)
        ]
        for fut in as_completed(futures):
            yield fut.result()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# ----------------------------------------------------------------------------------------------
# The runner
# ----------------------------------------------------------------------------------------------


@dataclass
class SweepResult:
    """What a run produced: rows of results.csv (job order), pair rows, and the output paths."""

    out_dir: Path
    jobs: list[Job]
    rows: list[dict]
    pairs: list[dict]
    rendered: int
    files: dict[str, Path]


class SweepRunner:
    """Run a :class:`Sweep` into ``out_dir`` (see the module docstring).

    ``workers``: jobs at once (1: in this process, the renderer using every core; more: a
    ``executor`` = "process" (default) or "thread" pool, each job's tiles on cores / workers
    threads).  ``scheduler`` ("tcp://host:port") or ``dask_local`` (number of local workers)
    run the jobs on Dask instead.  ``resume``: continue in a folder that has results; without
    it such a folder is an error unless ``overwrite`` (which starts afresh).
    """

    def __init__(
        self,
        sweep: Sweep,
        out_dir: str | Path,
        *,
        workers: int = 1,
        executor: str = "process",
        scheduler: str | None = None,
        dask_local: int | None = None,
        resume: bool = False,
        overwrite: bool = False,
        progress: bool = True,
        device: str | None = None,
        threads: int | None = None,
    ):
        if workers < 1:
            raise InputError("must be >= 1", field="--workers", value=workers)
        if executor not in ("process", "thread"):
            raise InputError("unknown executor", field="executor", value=executor, allowed="process, thread")
        if scheduler and dask_local:
            raise InputError("give either --scheduler or --dask-local", field="--scheduler")
        if dask_local is not None and dask_local < 1:
            raise InputError("must be >= 1", field="--dask-local", value=dask_local)
        self.sweep = sweep
        self.out_dir = Path(out_dir)
        self.workers = int(workers)
        self.executor = executor
        self.scheduler = scheduler
        self.dask_local = dask_local
        self.resume = resume
        self.overwrite = overwrite
        self.progress = progress
        self.device = device
        self.threads = threads

    # -- paths -------------------------------------------------------------------------------

    @property
    def results_path(self) -> Path:
        return self.out_dir / "results.csv"

    def image_path(self, job: Job, view: str, ext: str) -> Path:
        first = self.sweep.views[0].name
        name = job.key if view == first else f"{job.key}.{view}"
        return self.out_dir / "images" / f"{name}.{ext}"

    def header(self) -> list[str]:
        return (
            ["index", "key", "label"]
            + [a.name for a in self.sweep.axes]
            + self.sweep.columns()
            + ["rays", "seconds", "image"]
        )

    # -- run ---------------------------------------------------------------------------------

    def run(self) -> SweepResult:
        sw = self.sweep
        jobs = sw.jobs()
        sw.validate(jobs)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        with self._lock():
            header = self.header()
            done = self._prepare_results(header, jobs)
            _write_text_atomic(
                self.out_dir / "sweep.json",
                json.dumps(
                    {
                        "name": sw.name,
                        "description": sw.description,
                        "source": sw.source,
                        "mode": sw.mode,
                        "axes": [{"name": a.name, "path": a.path, "values": list(a.values)} for a in sw.axes],
                        "views": [_view_settings(v) for v in sw.views],
                        "jobs": [
                            {
                                "index": j.index,
                                "key": j.key,
                                "label": j.label,
                                "overrides": j.overrides,
                                "views": j.views,
                            }
                            for j in jobs
                        ],
                    },
                    indent=1,
                    default=repr,
                )
                + "\n",
            )
            pending = [j for j in jobs if j.key not in done]
            rendered = self._execute(pending, header, len(jobs) - len(pending), len(jobs))
            return self._finalize(jobs, header, rendered)

    @contextlib.contextmanager
    def _lock(self):
        import fcntl

        f = open(self.out_dir / ".sweep.lock", "w")  # not-a-replace: an flock target, holds no data
        try:
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                raise InputError("another sweep is running in this folder", file=str(self.out_dir)) from None
            yield
        finally:
            f.close()

    def _prepare_results(self, header: list[str], jobs: list[Job]) -> set[str]:
        path = self.results_path
        existing_header, rows = read_results(path, repair=True)
        if existing_header is not None and not (self.resume or self.overwrite):
            raise InputError(
                "this folder has results already: pass --resume to continue the sweep, or "
                "--overwrite to start again",
                file=str(path),
            )
        if existing_header is not None and existing_header != header and not self.overwrite:
            raise InputError(
                "results.csv has other columns (another sweep definition?): use another folder "
                "or --overwrite",
                file=str(path),
            )
        if existing_header is None or self.overwrite:
            _write_text_atomic(path, _csv_line(header))
            return set()
        keys = {j.key for j in jobs}
        return {r["key"] for r in rows if r["key"] in keys}

    def _payload(self, job: Job, data, path, threads) -> dict:
        return {
            "scene_data": data,
            "scene_path": path,
            "sweep_dir": str(self.sweep.base_dir),
            "job": {
                "index": job.index,
                "key": job.key,
                "overrides": job.overrides,
                "views": [list(v) for v in job.views],
            },
            "views": [_view_settings(v) for v in self.sweep.views],
            "device": self.device,
            "threads": threads,
        }

    def _execute(self, pending: list[Job], header: list[str], done: int, total: int) -> int:
        if not pending:
            return 0
        data, path, _ = self.sweep.scene_source()
        from .device import cpu_threads

        parallel = self.dask_local or (1 if self.scheduler else self.workers)
        threads = self.threads or (max(1, cpu_threads() // parallel) if parallel > 1 else None)
        payloads = [self._payload(j, data, path, threads) for j in pending]
        by_key = {j.key: j for j in pending}
        if self.scheduler or self.dask_local:
            results = _dask_results(payloads, scheduler=self.scheduler, dask_local=self.dask_local)
        elif self.workers > 1:
            results = _pool_results(payloads, self.workers, self.executor)
        else:
            results = _local_results(payloads)
        bar = None
        if self.progress:
            from tqdm.auto import tqdm  # a widget in Jupyter, text in a terminal

            bar = tqdm(
                total=total,
                initial=done,
                unit="job",
                desc=self.sweep.name,
                dynamic_ncols=True,
                file=sys.stderr,
            )
        n = 0
        try:
            for res in results:
                self._record(by_key[res["key"]], res, header)
                n += 1
                if bar is not None:
                    bar.update(1)
        finally:
            if bar is not None:
                bar.close()
            with contextlib.suppress(Exception):
                results.close()
        return n

    def _record(self, job: Job, res: dict, header: list[str]) -> None:
        from .render import Image

        for vname, arrs in res["images"].items():
            img = Image(
                xyz=arrs["xyz"],
                stokes=arrs["stokes"],
                alpha=arrs["alpha"],
                exposure=arrs["exposure"],
                tone=arrs["tone"],
            )
            img.save(self.image_path(job, vname, "exr"))
            img.save(self.image_path(job, vname, "png"))
        first = self.sweep.views[0].name
        image = self.image_path(job, first, "png").relative_to(self.out_dir) if first in res["images"] else ""
        row = {
            "index": job.index,
            "key": job.key,
            "label": job.label,
            **job.labels,
            **res["metrics"],
            "rays": res["rays"],
            "seconds": f"{res['seconds']:.3f}",
            "image": str(image),
        }
        _append_line(
            self.results_path,
            _csv_line([_format_value(row[h]) if not isinstance(row[h], str) else row[h] for h in header]),
        )

    # -- outputs -----------------------------------------------------------------------------

    def _finalize(self, jobs: list[Job], header: list[str], rendered: int) -> SweepResult:
        _h, rows = read_results(self.results_path)
        by_key = {}
        for r in rows:
            by_key.setdefault(r["key"], r)
        ordered = [by_key[j.key] for j in jobs if j.key in by_key]
        text = _csv_line(header) + "".join(_csv_line([r[h] for h in header]) for r in ordered)
        _write_text_atomic(self.results_path, text)
        files = {"results": self.results_path}
        complete = len(ordered) == len(jobs)
        pairs = self._pairs(jobs, by_key) if complete and self.sweep.compare else []
        if pairs:
            files["pairs"] = self.out_dir / "pairs.csv"
        if complete:
            files["contact_sheet"] = self._contact_sheet(jobs, pairs)
            files.update(self._plots(jobs, by_key, pairs))
            files["summary"] = self._summary(jobs, by_key, pairs, rendered)
        return SweepResult(
            out_dir=self.out_dir, jobs=jobs, rows=ordered, pairs=pairs, rendered=rendered, files=files
        )

    def _read_xyz_alpha(self, job: Job):
        from .image import read_image

        px, names = read_image(self.image_path(job, self.sweep.views[0].name, "exr"))
        idx = {n: i for i, n in enumerate(names)}
        xyz = px[..., [idx["X"], idx["Y"], idx["Z"]]].astype(np.float64)
        return xyz, px[..., idx["A"]].astype(np.float64)

    def _pairs(self, jobs: list[Job], by_key: dict) -> list[dict]:
        from . import metrics as wm
        from .image import write_png

        cmp = self.sweep.compare
        if not self.sweep.views[0].save:
            return []
        others = [a.name for a in self.sweep.axes if a.name != cmp.axis]

        def sig(j):
            return json.dumps([j.values[n] for n in others], sort_keys=True, default=repr)

        refs = {sig(j): j for j in jobs if j.values[cmp.axis] == cmp.reference}
        out = []
        for j in jobs:
            if j.values[cmp.axis] == cmp.reference or sig(j) not in refs:
                continue
            r = refs[sig(j)]
            xa, aa = self._read_xyz_alpha(j)
            xb, ab = self._read_xyz_alpha(r)
            de = wm.delta_e_image(xa, xb)
            st = wm.delta_e_stats(de, aa, ab)
            st["dE_mean_color"] = wm.delta_e_mean_color(xa, aa, xb, ab)
            diff = self.out_dir / "diffs" / f"{j.key}__vs__{r.key}.png"
            write_png(diff, wm.difference_image(de, scale=cmp.scale))
            out.append(
                {
                    "index": j.index,
                    "key": j.key,
                    "reference_key": r.key,
                    "label": j.label,
                    **{n: j.labels[n] for n in others},
                    cmp.axis: j.labels[cmp.axis],
                    **st,
                    "diff_image": str(diff.relative_to(self.out_dir)),
                }
            )
        if out:
            hdr = list(out[0])
            _write_text_atomic(
                self.out_dir / "pairs.csv",
                _csv_line(hdr)
                + "".join(
                    _csv_line([_format_value(p[h]) if not isinstance(p[h], str) else p[h] for h in hdr])
                    for p in out
                ),
            )
        return out

    def _contact_sheet(self, jobs: list[Job], pairs: list[dict]) -> Path:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from .image import atomic_path, read_image

        tiles = []
        for j in jobs:
            p = self.image_path(j, self.sweep.views[0].name, "png")
            tiles.append((read_image(p)[0] if p.is_file() else None, j.label))
        for pr in pairs:
            tiles.append(
                (
                    read_image(self.out_dir / pr["diff_image"])[0],
                    f"ΔE00 {pr['label']}\nmean {pr['dE_mean']:.2f}, p95 {pr['dE_p95']:.1f}",
                )
            )
        last = self.sweep.axes[-1]
        ncols = (
            len(last.values)
            if self.sweep.mode == "product" and 1 < len(last.values) <= 8
            else max(1, math.ceil(math.sqrt(len(tiles))))
        )
        nrows = math.ceil(len(tiles) / ncols)
        fig, axs = plt.subplots(nrows, ncols, figsize=(2.0 * ncols, 2.25 * nrows), squeeze=False)
        for ax in axs.ravel():
            ax.axis("off")
        for ax, (img, label) in zip(axs.ravel(), tiles, strict=False):
            if img is not None:
                ax.imshow(np.clip(img[..., :3], 0, 1), interpolation="nearest")
            ax.set_title(label, fontsize=7)
        fig.suptitle(self.sweep.name, fontsize=9)
        fig.tight_layout()
        out = self.out_dir / "contact_sheet.png"
        with atomic_path(out) as tmp:
            fig.savefig(tmp, dpi=100, format="png")
        plt.close(fig)
        return out

    def _plot_columns(self) -> list[str]:
        cols = []
        several = len(self.sweep.views) > 1
        for v in self.sweep.views:
            for m in v.metrics:
                for c in _PLOTTED_COLOR_COLUMNS if m == "color" else METRICS[m]:
                    cols.append(f"{v.name}_{c}" if several else c)
        return cols

    def _plots(self, jobs: list[Job], by_key: dict, pairs: list[dict]) -> dict[str, Path]:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from .image import atomic_path

        files = {}
        pair_by_key = {p["key"]: p for p in pairs}
        series = [(c, lambda j, c=c: float(by_key[j.key][c]), jobs) for c in self._plot_columns()]
        if pairs:
            pj = [j for j in jobs if j.key in pair_by_key]
            series += [
                (c, lambda j, c=c: float(pair_by_key[j.key][c]), pj) for c in ("dE_mean", "dE_mean_color")
            ]
        for col, get, subset in series:
            for ax_def in self.sweep.axes:
                multi = [a for a in self.sweep.axes if len(a.values) > 1]
                if len(ax_def.values) < 2 or (
                    pairs
                    and col.startswith("dE")
                    and ax_def.name == self.sweep.compare.axis
                    and len(multi) > 1
                ):
                    continue  # ΔE against the compared axis only when it is the only one
                numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in ax_def.values)
                others = [a for a in self.sweep.axes if a.name != ax_def.name and len(a.values) > 1]
                lines: dict[str, list] = {}
                for j in subset:
                    name = ", ".join(f"{a.name}={j.labels[a.name]}" for a in others) or col
                    x = j.values[ax_def.name] if numeric else ax_def.values.index(j.values[ax_def.name])
                    lines.setdefault(name, []).append((x, get(j)))
                fig, ax = plt.subplots(figsize=(5.0, 3.4))
                for name, pts in lines.items():
                    pts.sort(key=lambda t: t[0])
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=name)
                if not numeric:
                    ax.set_xticks(range(len(ax_def.values)))
                    ax.set_xticklabels([ax_def.label_of(i) for i in range(len(ax_def.values))], fontsize=7)
                elif all(v > 0 for v in ax_def.values) and max(ax_def.values) / min(ax_def.values) >= 100:
                    ax.set_xscale("log")
                ys = [y for pts in lines.values() for _x, y in pts]
                if ys and min(ys) > 0 and max(ys) / min(ys) >= 100:
                    ax.set_yscale("log")  # e.g. ΔE over decades of stone size
                ax.set_xlabel(ax_def.name + (f"  ({ax_def.path})" if ax_def.path else ""))
                ax.set_ylabel(col)
                ax.grid(alpha=0.3)
                if len(lines) > 1:
                    ax.legend(fontsize=6)
                ax.set_title(f"{self.sweep.name}: {col} vs {ax_def.name}", fontsize=9)
                fig.tight_layout()
                out = self.out_dir / "plots" / f"{_slug(col)}_vs_{_slug(ax_def.name)}.png"
                out.parent.mkdir(parents=True, exist_ok=True)
                with atomic_path(out) as tmp:
                    fig.savefig(tmp, dpi=100, format="png")
                plt.close(fig)
                files[f"plot:{col}:{ax_def.name}"] = out
        return files

    def _summary(self, jobs: list[Job], by_key: dict, pairs: list[dict], rendered: int) -> Path:
        sw = self.sweep
        rows = [by_key[j.key] for j in jobs]
        cols = self._plot_columns()
        lines = [f"# Sweep: {sw.name}", ""]
        if sw.description:
            lines += [sw.description, ""]
        seconds = sum(float(r["seconds"]) for r in rows)
        shape = " x ".join(f"{a.name} ({len(a.values)})" for a in sw.axes)
        lines += [
            f"- base scene: `{sw.scene if not hasattr(sw.scene, 'path') else sw.scene.path}`",
            f"- {len(jobs)} jobs ({sw.mode} of {shape}); rendered in this run: {rendered}; "
            f"render time of all jobs: {seconds:.1f} s",
            "- views: " + "; ".join(f"{v.name} ({', '.join(v.metrics)})" for v in sw.views),
            "",
        ]
        lines += [
            "## Results",
            "",
            "| job | " + " | ".join(a.name for a in sw.axes) + " | " + " | ".join(cols) + " |",
            "|" + "---|" * (1 + len(sw.axes) + len(cols)),
        ]
        for j, r in zip(jobs, rows, strict=True):
            lines.append(
                f"| {j.index} | "
                + " | ".join(j.labels[a.name] for a in sw.axes)
                + " | "
                + " | ".join(_fmt_num(r[c]) for c in cols)
                + " |"
            )
        lines.append("")
        if len(jobs) > 1:
            lines += ["## Extremes", ""]
            for c in cols:
                vals = [float(r[c]) for r in rows]
                hi, lo = int(np.argmax(vals)), int(np.argmin(vals))
                lines.append(
                    f"- {c}: max {_fmt_num(vals[hi])} at {jobs[hi].label}; "
                    f"min {_fmt_num(vals[lo])} at {jobs[lo].label}"
                )
            lines.append("")
        if pairs:
            cmp = sw.compare
            others = [a.name for a in sw.axes if a.name != cmp.axis]
            lines += [
                f"## Paired differences: {cmp.axis} vs {cmp.axis} = {_format_value(cmp.reference)}",
                "",
                "CIEDE2000 per pixel over the stones' pixels (mean, 95th percentile, max) and between the "
                "stones' mean colours; difference images in `diffs/` (full scale ΔE = "
                f"{cmp.scale:g}).",
                "",
                "| "
                + " | ".join(others + [cmp.axis])
                + " | ΔE mean | ΔE p95 | ΔE max | ΔE of means | image |",
                "|" + "---|" * (len(others) + 6),
            ]
            for p in pairs:
                lines.append(
                    "| "
                    + " | ".join(str(p[n]) for n in others + [cmp.axis])
                    + " | "
                    + " | ".join(f"{p[c]:.3f}" for c in _PAIR_COLUMNS)
                    + f" | [{Path(p['diff_image']).name}]"
                    f"({p['diff_image']}) |"
                )
            lines.append("")
        lines += [
            "## Files",
            "",
            "- `results.csv` — one row per job (metrics as defined in `warpoptics/metrics.py`)",
            "- `images/` — one EXR (RGB, A, S0-S3, XYZ) + PNG per job and view",
            "- `contact_sheet.png`",
            "- `plots/` — each metric against each axis",
        ]
        if pairs:
            lines.append("- `pairs.csv`, `diffs/` — paired ΔE and difference images")
        lines.append("")
        out = self.out_dir / "summary.md"
        _write_text_atomic(out, "\n".join(lines))
        return out


def _fmt_num(s) -> str:
    try:
        v = float(s)
    except (TypeError, ValueError):
        return str(s)
    return f"{v:.4g}"


def _slug(s: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", s)
