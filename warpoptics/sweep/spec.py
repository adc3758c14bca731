"""Sweep definitions: the TOML schema, its parsing and validation, and the jobs it expands to.

A :class:`Sweep` (``Sweep.load`` of a TOML file, ``Sweep.from_dict``, or ``Sweep(...)`` from
Python) is a base scene, axes of values addressed by dotted paths, fixed overrides, per-job
expressions (:mod:`warpoptics.sweep.expressions`), views and an optional paired comparison; see
:mod:`warpoptics.sweep` for the file format.  :meth:`Sweep.jobs` resolves every combination into
a :class:`Job` of plain, picklable overrides; :func:`scene_for` builds the scene of one job.
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import itertools
import json
import math
import re
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import validate as val
from ..errors import InputError
from .expressions import CONSTANTS, FUNCTIONS, evaluate_expression
from .results import format_value, job_key

__all__ = [
    "Axis",
    "View",
    "Compare",
    "Sweep",
    "Job",
    "METRICS",
    "MAX_JOBS",
    "referenced_files",
    "view_settings",
    "apply_overrides",
    "scene_for",
]

# metric name -> columns it adds to results.csv (per view)
METRICS: dict[str, tuple[str, ...]] = {
    "color": ("X", "Y", "Z", "L", "a", "b", "C", "h", "coverage"),
    "light_return": ("light_return",),
    "fire": ("fire",),
    "fire_excess": ("fire_nondispersive", "fire_excess"),
    "scintillation": ("scintillation",),
    # warpoptics.grading.performance: the face-up pattern's contrast and dark (extinct) area
    "contrast": ("contrast",),
    "extinction": ("extinction",),
}


# the most jobs one sweep expands to (see Sweep.combinations); at a second per tiny job that is a
# day of rendering, past which a sweep is a mistake or belongs in several folders
MAX_JOBS = 100_000

_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _check_name(name, *, file, field_name) -> str:
    if not isinstance(name, str) or not _NAME_RE.match(name) or name in FUNCTIONS or name in CONSTANTS:
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
        return self.labels[i] if self.labels is not None else format_value(self.values[i])


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
        pre = f"view.{self.name}."
        if not isinstance(self.tilts, (list, tuple)):
            raise InputError(
                "must be a list of [x, y, z] rotations in degrees", field=pre + "tilts", value=self.tilts
            )
        tilts = tuple(val.vec3(t, field=pre + "tilts") for t in self.tilts)
        if any(abs(c) > 360.0 for t in tilts for c in t):
            raise InputError(
                "a tilt is out of range",
                field=pre + "tilts",
                value=[list(t) for t in tilts],
                allowed="-360 to 360 degrees",
            )
        object.__setattr__(self, "tilts", tilts)
        object.__setattr__(
            self, "tilt_object", val.integer(self.tilt_object, field=pre + "tilt_object", lo=0)
        )
        object.__setattr__(
            self, "white_y", val.number(self.white_y, field=pre + "white_y", lo=0.0, lo_open=True)
        )
        object.__setattr__(
            self,
            "fire_min_saturation",
            val.number(self.fire_min_saturation, field=pre + "fire_min_saturation", lo=0.0, hi=1.0),
        )
        # "no" is a string, not false: a TOML boolean only
        object.__setattr__(self, "save", val.boolean(self.save, field=pre + "save"))
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
                    allowed=", ".join(format_value(v) for v in ax.values),
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
        if self.job_count() > MAX_JOBS:
            self.combinations()  # raises, with the count

    # -- loading -----------------------------------------------------------------------------

    @classmethod
    def load(cls, path: str | Path, *, extra_set: dict | None = None) -> Sweep:
        """Read a sweep TOML file; ``extra_set`` (dotted path -> value) is added to ``[set]``."""
        p = Path(path)
        data = val.toml_file(p, what="sweep")
        return cls.from_dict(data, base_dir=p.parent, source=str(p), extra_set=extra_set)

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
            except InputError as exc:  # the View's own checks: name the sweep file
                raise InputError(
                    exc.message, file=file, field=exc.field, value=exc.value, allowed=exc.allowed
                ) from None
        compare = None
        if "compare" in data:
            c = data["compare"]
            if not isinstance(c, dict):
                raise InputError("must be a table [compare]", file=file, field="compare", value=c)
            _check_keys(c, _COMPARE_KEYS, file=file, prefix="compare.")
            if "axis" not in c or "reference" not in c:
                raise InputError('needs axis = "name" and reference = value', file=file, field="compare")
            scale = val.number(c.get("scale", 10.0), file=file, field="compare.scale", lo=0.0, lo_open=True)
            compare = Compare(c["axis"], c["reference"], float(scale))
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
        from ..scene import Scene

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
        if (
            self.source is not None
            and Path(self.source).is_file()
            and p.resolve() == Path(self.source).resolve()
        ):
            raise InputError(
                "the base scene is this sweep file itself: name a scene TOML ([camera], [[object]], ...)",
                file=self.source,
                field="scene",
                value=str(self.scene),
            )
        try:
            text = p.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(
                f"not UTF-8 text (byte {exc.start}); TOML files are UTF-8", file=str(p)
            ) from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML ({exc})", file=str(p)) from None
        if "scene" in data and "axis" in data:
            raise InputError(
                "is a sweep file, not a scene: a sweep's base scene is a scene TOML",
                file=self.source,
                field="scene",
                value=str(self.scene),
            )
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

    def job_count(self) -> int:
        """The number of jobs, without enumerating them."""
        return math.prod(len(g[0].values) for g in self._groups())

    def combinations(self) -> list[dict[str, int]]:
        """Index of each axis's value, per job, in job order (first axis outermost).  More than
        :data:`MAX_JOBS` jobs are refused with the count (enumerating 10 million jobs alone takes
        minutes and gigabytes before the first render)."""
        groups = self._groups()
        n = self.job_count()
        if n > MAX_JOBS:
            shape = " x ".join(str(len(g[0].values)) for g in groups)
            raise InputError(
                f"{n:,} jobs ({shape}) is more than one sweep runs; split it into sweeps of at most "
                f"{MAX_JOBS:,} jobs",
                file=self.source,
                field="axis",
            )
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
        data, path, digest = self.scene_source()
        dirs = [Path(path).parent if path else None, self.base_dir]
        base_files = referenced_files(data, dirs)
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
            files = {**base_files, **referenced_files([overrides, views], dirs)}
            blob = json.dumps(
                {
                    "scene": digest,
                    "files": files,
                    "overrides": overrides,
                    "views": views,
                    "view_settings": [view_settings(v) for v in self.views],
                },
                sort_keys=True,
                default=repr,
            )
            key = job_key(index, blob)
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

    def identity(self) -> str:
        """What makes a folder's results this sweep's and no other's: its name, the base scene it
        names, its mode and its axes (names and paths, not their values: editing the values is
        the same sweep, continued).  Stored in ``sweep.json``; ``--resume`` refuses a folder of
        another identity."""
        scene = self.scene if isinstance(self.scene, (str, Path)) else getattr(self.scene, "path", None)
        blob = json.dumps(
            {
                "name": self.name,
                "scene": Path(str(scene)).name if scene else None,
                "mode": self.mode,
                "axes": [[a.name, a.path] for a in self.axes],
            },
            sort_keys=True,
        )
        return hashlib.sha1(blob.encode()).hexdigest()[:16]

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
        by_name = {v.name: v for v in self.views}
        for job in jobs if jobs is not None else self.jobs():
            for name, vo in job.views:
                scene = scene_for(data, path, {**job.overrides, **vo}, self.base_dir)
                view = by_name.get(name)
                if view is not None and "scintillation" in view.metrics:
                    count = len(scene.objects)
                    if not view.tilt_object < count:
                        objects = f"{count} object" + ("" if count == 1 else "s")
                        raise InputError(
                            f"no such object: the scene {path or ''} has {objects}",
                            file=self.source,
                            field=f"view.{name}.tilt_object",
                            value=view.tilt_object,
                            allowed=f"0 to {count - 1}" if count else "a scene with an [[object]]",
                        )


_DIGESTS: dict[tuple[str, int, int], str] = {}


def _file_digest(p: Path) -> str:
    """SHA-1 of a file's bytes, cached per (path, mtime, size) in this process."""
    st = p.stat()
    key = (str(p), st.st_mtime_ns, st.st_size)
    if key not in _DIGESTS:
        h = hashlib.sha1()
        with open(p, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                h.update(chunk)
        _DIGESTS[key] = h.hexdigest()
    return _DIGESTS[key]


def _strings(value):
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict):
        for v in value.values():
            yield from _strings(v)
    elif isinstance(value, (list, tuple)):
        for v in value:
            yield from _strings(v)


def referenced_files(value, dirs: Sequence[Path | str | None]) -> dict[str, str]:
    """``{path: content digest}`` of every string inside ``value`` (scene data, overrides) that
    names an existing file, absolute or relative to one of ``dirs`` (the base scene's folder, the
    sweep's).  Meshes, GemCAD designs, light maps, textures and material tables are all such
    strings; hashing whatever names a file keeps the list complete when a new field takes a file.
    Job keys include these digests, so that replacing a file a scene names re-renders its jobs."""
    out: dict[str, str] = {}
    for s in _strings(value):
        if not Path(s).suffix or len(s) > 4096 or "\0" in s:
            continue
        cands = [Path(s)] if Path(s).is_absolute() else [Path(d) / s for d in dirs if d is not None]
        for c in cands:
            try:
                if c.is_file():
                    out[str(c.resolve())] = _file_digest(c)
            except OSError:
                continue
    return out


def view_settings(v: View) -> dict:
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


_MAP_RE = re.compile(r"^light\.\d+\.map$")
_MATERIAL_RE = re.compile(r"^(object\.\d+\.material)\.")


def _resolve_map(value, base: Path | None):
    if isinstance(value, str) and Path(value).suffix and not Path(value).is_absolute() and base is not None:
        return str((base / value).resolve())
    return value


def apply_overrides(data: dict, overrides: dict, *, file: str = "<scene>") -> dict:
    """A deep copy of raw scene ``data`` with dotted ``overrides`` set (see the module
    docstring: a material name becomes ``{ base = name }`` when a path reaches below it)."""
    from ..scene import set_dotted

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
    from ..scene import Scene

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
