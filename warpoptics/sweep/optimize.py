"""The cut optimizer: maximize a light-performance metric (or a weighted mix) over cut parameters.

:class:`CutOptimizer` searches the box of :class:`Parameter` s (dotted paths into the stone's
``[[object]]`` table: ``object.0.pavilion_angle``, ``object.0.crown_angle``, ``object.0.table``,
any keyword of a parametric cut) for the maximum of

    J = sum_k w_k M_k

where M_k are the protocol metrics of :func:`warpoptics.sweep.grading.protocol_scores`
(``light_return``, ``contrast``, ``extinction``, ``fire``, ``scintillation``: the tilted,
head-obscured protocol of :mod:`warpoptics.grading.performance`) and w_k the ``objective``
weights (negative to penalise, e.g. extinction).  The search is CMA-ES (N. Hansen's ``cma``
package, ``cma.CMAEvolutionStrategy``; Hansen & Ostermeier 2001), gradient-free, on the
parameters scaled to [0, 1] with ``cma``'s bound transform; its random numbers come from a
seeded generator of its own (``randn`` option), so a run is a deterministic function of its
settings and of the metric values it is told.

**Constraints** (:class:`Constraints`: total depth and table within ranges, weight retention
V / V_rough at least a minimum against the elliptic-cylinder rough of height ``rough_height``)
are checked on the geometry before anything is rendered; a violating or unbuildable candidate
costs no render: CMA-ES is told 1 + its total relative violation, worse than any feasible value.

Parallel and resumable: each generation's feasible candidates are one zipped protocol sweep
run by :class:`~warpoptics.sweep.SweepRunner` (a pool or Dask), every evaluation is journalled
(``journal.csv``), and ``resume=True`` replays the search without rendering again what the
journal holds; docs/design/cut_optimizer.md has the layout and the Dask cluster's reuse.

**GemCAD tier angles** are parameters like any keyword: ``object.0.tier_angles.<tier>`` (a tier
name or ``#k``, :func:`warpoptics.geometry.gemcad.recut_tiers`: the tier re-cut at the angle
through its innermost meet point); ``best.asc`` is then the re-cut design with its names.

**Outputs** (atomic): ``best.asc`` (the best design, GemCAD, ``geometry.gemcad.write``),
``report.md`` and ``report.json`` (settings, the best parameters and metrics, renders spent),
``trace.png`` (J per evaluation and the best so far) and, for two parameters,
``parameters.png`` (the evaluated points over the parameter plane).

Reference: N. Hansen, A. Ostermeier, "Completely derandomized self-adaptation in evolution
strategies", Evolutionary Computation 9(2), 159-195 (2001); ``cma`` (pypi.org/project/cma).
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import hashlib
import json
import math
import shutil
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..grading.performance import PROTOCOL, Protocol
from .backends import local_cluster
from .grading import SPOT_METRICS, protocol_scene, protocol_scores, protocol_sweep, renders_per_job
from .results import append_line, csv_line, format_value, read_results, write_text_atomic
from .runner import SweepRunner
from .spec import Axis

__all__ = ["Parameter", "Constraints", "OBJECTIVE_METRICS", "CutOptimizer", "stone_mesh"]

OBJECTIVE_METRICS = ("light_return", "contrast", "extinction", "fire", "scintillation")
_NAME_OK = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_")


@dataclass(frozen=True)
class Parameter:
    """A searched parameter: ``name`` (an identifier: the sweep axis and journal column), ``path``
    (dotted, into the scene: ``object.0.<keyword>``), the box [``low``, ``high``] and the start
    (default the middle)."""

    name: str
    path: str
    low: float
    high: float
    start: float | None = None

    def __post_init__(self):
        if not self.name or not set(self.name) <= _NAME_OK or self.name[0].isdigit():
            raise InputError("must be an identifier", field="parameter.name", value=self.name)
        if not self.path.startswith("object.0."):
            raise InputError(
                "must be a path into the stone, object.0.<keyword>",
                field=f"{self.name}.path",
                value=self.path,
            )
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise InputError("needs low < high", field=f"{self.name}.bounds", value=(self.low, self.high))
        s = self.start if self.start is not None else 0.5 * (self.low + self.high)
        if not self.low <= s <= self.high:
            raise InputError(
                "the start must lie within the bounds",
                field=f"{self.name}.start",
                value=s,
                allowed=f"[{self.low}, {self.high}]",
            )
        object.__setattr__(self, "start", float(s))

    def scaled(self, v: float) -> float:
        return (v - self.low) / (self.high - self.low)

    def value(self, u: float) -> float:
        # rounded to 1e-9: the value rendered, written to the journal and looked up in it
        return round(self.low + min(1.0, max(0.0, float(u))) * (self.high - self.low), 9)


@dataclass(frozen=True)
class Constraints:
    """Geometric constraints of a candidate (module docstring); ``None``: no constraint.
    ``depth`` and ``table``: (min, max) fractions of the girdle width; ``min_weight_retention``:
    V / V_rough; ``rough_height``: the rough's height / width."""

    depth: tuple[float, float] | None = None
    table: tuple[float, float] | None = None
    min_weight_retention: float | None = None
    rough_height: float = 1.0

    def __post_init__(self):
        for name in ("depth", "table"):
            r = getattr(self, name)
            if r is not None:
                if len(r) != 2 or not 0 <= r[0] < r[1]:
                    raise InputError("must be (min, max) with 0 <= min < max", field=name, value=r)
                object.__setattr__(self, name, (float(r[0]), float(r[1])))
        w = self.min_weight_retention
        if w is not None and not 0 < w < 1:
            raise InputError("must be in (0, 1)", field="min_weight_retention", value=w)
        if not self.rough_height > 0:
            raise InputError("must be > 0", field="rough_height", value=self.rough_height)

    def measure(self, mesh) -> dict[str, float]:
        """``depth``, ``table`` (fractions of the width) and ``weight_retention`` of ``mesh``."""
        from ..geometry.cuts import measure_proportions

        pr = mesh.metadata.get("proportions") or measure_proportions(mesh)
        rough = math.pi / 4 * pr.length * pr.width * self.rough_height * pr.width
        return {
            "depth": float(pr.total_depth),
            "table": float(pr.table),
            "weight_retention": float(mesh.volume / rough),
        }

    def violation(self, measured: dict[str, float]) -> float:
        """Sum of the relative violations (0: feasible)."""
        v = 0.0
        for name in ("depth", "table"):
            r = getattr(self, name)
            if r is not None:
                x = measured[name]
                v += max(0.0, r[0] - x) / r[0] if r[0] > 0 else 0.0
                v += max(0.0, x - r[1]) / r[1]
        if self.min_weight_retention is not None:
            v += (
                max(0.0, self.min_weight_retention - measured["weight_retention"]) / self.min_weight_retention
            )
        return float(v)


def stone_mesh(stone: dict):
    """The mesh of a stone's ``[[object]]`` table, built as the renderer builds it."""
    from ..pipelines.objects import build_objects

    scene = protocol_scene(stone, Protocol(size=4, wavelengths=1))
    return build_objects(scene.objects, file=None).meshes[0][0]


def _set_path(stone: dict, path: str, value) -> dict:
    out = copy.deepcopy(stone)
    keys = path.split(".")[2:]
    node = out
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value
    return out


@dataclass
class _Eval:
    index: int
    generation: int
    candidate: int
    values: dict
    feasible: bool
    violation: float
    measured: dict
    metrics: dict = field(default_factory=dict)
    objective: float = float("nan")
    renders: int = 0


class CutOptimizer:
    """CMA-ES over cut parameters (module docstring).

    ``stone``: the base ``[[object]]`` table; ``parameters``: :class:`Parameter` s;
    ``objective``: metric -> weight (default ``{"light_return": 1.0}``); ``protocol``: the views
    and image size of every evaluation; ``budget``: the most evaluations that render (whole
    generations: the search stops before one that would exceed it); ``popsize`` (default
    CMA-ES's 4 + 3 ln N) and ``sigma0`` (initial step, in units of each parameter's range);
    ``seed``.  ``runner_kw`` go to each generation's :class:`SweepRunner` (``workers``,
    ``dask_local``, ``scheduler``, ``executor``, ``device``, ``progress``)."""

    def __init__(
        self,
        stone: dict,
        parameters: Sequence[Parameter],
        out_dir: str | Path,
        *,
        objective: dict[str, float] | None = None,
        protocol: Protocol = PROTOCOL,
        constraints: Constraints | None = None,
        budget: int = 40,
        popsize: int | None = None,
        sigma0: float = 0.25,
        seed: int = 1,
        frame_mm: float | None = None,
        resume: bool = False,
        overwrite: bool = False,
        **runner_kw,
    ):
        self.stone = dict(stone)
        self.parameters = tuple(parameters)
        if not self.parameters:
            raise InputError("needs at least one parameter", field="parameters")
        names = [p.name for p in self.parameters]
        if len(set(names)) != len(names):
            raise InputError("parameter names must be unique", field="parameters", value=names)
        self.objective = dict(objective or {"light_return": 1.0})
        for k, w in self.objective.items():
            if k not in OBJECTIVE_METRICS:
                raise InputError(
                    "unknown metric", field="objective", value=k, allowed=", ".join(OBJECTIVE_METRICS)
                )
            if not math.isfinite(w):
                raise InputError("weights must be finite", field=f"objective.{k}", value=w)
        if not any(w != 0 for w in self.objective.values()):
            raise InputError("needs a non-zero weight", field="objective", value=self.objective)
        self.fire = any(self.objective.get(m, 0.0) != 0 for m in SPOT_METRICS)
        self.protocol = protocol
        self.constraints = constraints or Constraints()
        if budget < 1:
            raise InputError("must be >= 1", field="budget", value=budget)
        self.budget = int(budget)
        n = len(self.parameters)
        self.popsize = int(popsize) if popsize is not None else 4 + int(3 * math.log(n))
        if self.popsize < 2:
            raise InputError("must be >= 2", field="popsize", value=popsize)
        if self.budget < self.popsize:
            # a generation renders all of its feasible candidates or none: a smaller budget
            # would stop before the first one
            raise InputError(
                f"is smaller than one generation of {self.popsize} candidates: give a budget >= "
                f"{self.popsize} or a smaller popsize",
                field="budget",
                value=self.budget,
            )
        if not 0 < sigma0 <= 1:
            raise InputError("must be in (0, 1]", field="sigma0", value=sigma0)
        self.sigma0 = float(sigma0)
        self.seed = int(seed)
        self.frame_mm = frame_mm
        self.out_dir = Path(out_dir)
        self.resume = resume
        self.overwrite = overwrite
        runner_kw.setdefault("progress", False)
        nd = runner_kw.get("dask_local")
        if nd is not None and (isinstance(nd, bool) or not isinstance(nd, int) or nd < 1):
            raise InputError("must be an integer >= 1", field="--dask-local", value=nd)
        if nd and runner_kw.get("scheduler"):
            raise InputError("give either --scheduler or --dask-local", field="--scheduler")
        self.runner_kw = runner_kw
        self._stack: contextlib.ExitStack | None = None
        self._cluster_kw: dict | None = None

    # -- settings and journal --------------------------------------------------------------------

    def settings(self) -> dict:
        return {
            "stone": self.stone,
            "parameters": [asdict(p) for p in self.parameters],
            "objective": self.objective,
            "protocol": asdict(self.protocol),
            "constraints": asdict(self.constraints),
            "popsize": self.popsize,
            "sigma0": self.sigma0,
            "seed": self.seed,
            "frame_mm": self.frame_mm,
        }

    @property
    def journal_path(self) -> Path:
        return self.out_dir / "journal.csv"

    def header(self) -> list[str]:
        return [
            "eval",
            "generation",
            "candidate",
            *[p.name for p in self.parameters],
            "feasible",
            "violation",
            "depth",
            "table",
            "weight_retention",
            *OBJECTIVE_METRICS,
            "objective",
            "renders",
        ]

    def _key(self, values: dict) -> str:
        return json.dumps([format_value(float(values[p.name])) for p in self.parameters])

    def _prepare(self) -> dict[str, dict]:
        self.out_dir.mkdir(parents=True, exist_ok=True)
        settings = json.dumps(self.settings(), sort_keys=True, default=repr)
        digest = hashlib.sha1(settings.encode()).hexdigest()
        meta = self.out_dir / "optimizer.json"
        header, rows = read_results(self.journal_path, repair=True)
        if header is not None and self.overwrite:
            header, rows = None, []
            shutil.rmtree(self.out_dir / "generations", ignore_errors=True)
        if header is not None:
            if not self.resume:
                raise InputError(
                    "this folder has an optimizer journal: pass --resume to continue, or --overwrite",
                    file=str(self.journal_path),
                )
            old = json.loads(meta.read_text()).get("digest") if meta.is_file() else None
            if header != self.header() or old != digest:
                raise InputError(
                    "the journal was written with other settings: use another folder or --overwrite",
                    file=str(self.journal_path),
                )
        else:
            write_text_atomic(self.journal_path, csv_line(self.header()))
        write_text_atomic(meta, json.dumps({"digest": digest, "settings": self.settings()}, indent=1) + "\n")
        return {self._key(r): r for r in rows}

    def _journal(self, e: _Eval) -> None:
        def cell(v: float) -> str:
            """A number, or an empty cell for what was not measured (an infeasible candidate's
            objective, a metric the objective does not need): no NaN in the file."""
            return format_value(float(v)) if math.isfinite(v) else ""

        m = {k: e.metrics.get(k, float("nan")) for k in OBJECTIVE_METRICS}
        row = [
            e.index,
            e.generation,
            e.candidate,
            *[format_value(float(e.values[p.name])) for p in self.parameters],
            "true" if e.feasible else "false",
            cell(e.violation),
            *[cell(e.measured[k]) for k in ("depth", "table", "weight_retention")],
            *[cell(m[k]) for k in OBJECTIVE_METRICS],
            cell(e.objective),
            e.renders,
        ]
        append_line(self.journal_path, csv_line(row))

    def _from_row(self, row: dict, e: _Eval) -> _Eval:
        """``e`` filled from a journal row, which is checked first: numbers where numbers belong,
        a finite objective on a feasible row, and that objective equal to J of the row's own
        metrics (an edited objective, e.g. 1e308, is not trusted as the best result)."""
        where = f"journal row eval {row.get('eval', '?')}"

        def num(name: str) -> float:
            if row.get(name) == "":  # not measured (journals before this read "nan")
                return math.nan
            try:
                return float(row[name])
            except (KeyError, TypeError, ValueError):
                raise InputError(
                    f"{where}: not a number", file=str(self.journal_path), field=name, value=row.get(name)
                ) from None

        if row.get("feasible") not in ("true", "false"):
            raise InputError(
                f"{where}: must be true or false",
                file=str(self.journal_path),
                field="feasible",
                value=row.get("feasible"),
            )
        feasible = row["feasible"] == "true"
        violation = num("violation")
        metrics = {k: num(k) for k in OBJECTIVE_METRICS if row.get(k) not in ("", "nan")}
        objective = num("objective")
        if feasible:
            bad = [k for k in self.objective if not math.isfinite(metrics.get(k, math.nan))]
            if bad or not math.isfinite(objective):
                field = bad[0] if bad else "objective"
                raise InputError(
                    f"{where}: a feasible candidate needs finite metrics and objective: use --overwrite "
                    "to start again",
                    file=str(self.journal_path),
                    field=field,
                    value=row.get(field),
                )
            expected = self.score(metrics)
            if not math.isclose(objective, expected, rel_tol=1e-9, abs_tol=1e-12):
                raise InputError(
                    f"{where}: the objective is not J of the row's metrics ({expected!r}); the journal "
                    "was edited or damaged: use --overwrite to start again",
                    file=str(self.journal_path),
                    field="objective",
                    value=row["objective"],
                )
        elif not (math.isfinite(violation) and violation > 0.0):
            raise InputError(
                f"{where}: an infeasible candidate needs a violation > 0",
                file=str(self.journal_path),
                field="violation",
                value=row["violation"],
            )
        e.feasible = feasible
        e.violation = violation
        e.metrics = metrics
        e.objective = objective
        e.renders = 0  # rendered by an earlier run
        return e

    # -- the search ------------------------------------------------------------------------------

    def score(self, metrics: dict[str, float]) -> float:
        """J = sum_k w_k M_k (module docstring)."""
        return float(sum(w * metrics[k] for k, w in self.objective.items()))

    def candidate_stone(self, values: dict) -> dict:
        st = self.stone
        for p in self.parameters:
            st = _set_path(st, p.path, float(values[p.name]))
        return st

    def _evaluate_generation(self, gen: int, evals: list[_Eval]) -> int:
        todo = [e for e in evals if e.feasible and math.isnan(e.objective)]
        if not todo:
            return 0
        axes = [
            Axis(p.name, tuple(float(e.values[p.name]) for e in todo), path=p.path) for p in self.parameters
        ]
        sweep = protocol_sweep(
            self.stone,
            self.protocol,
            axes=axes,
            mode="zip",
            fire=self.fire,
            frame_mm=self.frame_mm,
            name=f"optimize_g{gen:03d}",
        )
        folder = self.out_dir / "generations" / f"g{gen:03d}"
        res = SweepRunner(sweep, folder, resume=True, **self._generation_kw()).run()
        if len(res.rows) != len(todo):
            raise InputError("a generation's sweep did not finish", file=str(folder / "results.csv"))
        per = renders_per_job(sweep)
        for e, row in zip(todo, res.rows, strict=True):
            e.metrics = protocol_scores(row, self.protocol, fire=self.fire)
            e.objective = self.score(e.metrics)
        for e in todo:
            e.renders = per  # the cost of an evaluation (res.rendered: how many this run paid)
        spent = res.rendered * per
        return spent

    def _generation_kw(self) -> dict:
        """The generations' :class:`SweepRunner` keywords: ``runner_kw``, with ``dask_local``
        replaced by the address of the run's one local cluster (started on first use)."""
        n = self.runner_kw.get("dask_local")
        if not n:
            return self.runner_kw
        if self._cluster_kw is None:
            from ..device import cpu_threads

            assert self._stack is not None, "generations run inside run()"
            address = self._stack.enter_context(local_cluster(int(n)))
            kw = {**self.runner_kw, "dask_local": None, "scheduler": address}
            if kw.get("threads") is None:
                kw["threads"] = max(1, cpu_threads() // int(n))
            self._cluster_kw = kw
        return self._cluster_kw

    def run(self) -> dict:
        with contextlib.ExitStack() as stack:
            self._stack, self._cluster_kw = stack, None
            try:
                return self._run()
            finally:
                self._stack = self._cluster_kw = None

    def _check_parameters(self) -> None:
        """Errors of the parameters themselves, before any search: the scene at each parameter's
        bounds (an unknown GemCAD tier, an angle out of range) and the stone at the start."""
        start = {p.name: float(p.start) for p in self.parameters}  # type: ignore[arg-type]
        for p in self.parameters:
            for v in (p.low, p.high):
                protocol_scene(self.candidate_stone({**start, p.name: v}), Protocol(size=4, wavelengths=1))
        stone_mesh(self.candidate_stone(start))

    def _run(self) -> dict:
        import cma

        self._check_parameters()
        journal = self._prepare()
        rng = np.random.default_rng(self.seed)
        x0 = [p.scaled(float(p.start)) for p in self.parameters]  # type: ignore[arg-type]
        opts = {
            "bounds": [0.0, 1.0],
            "popsize": self.popsize,
            "seed": np.nan,  # cma leaves numpy's global generator alone; ours comes through randn
            "randn": lambda *shape: rng.standard_normal(shape),
            "verbose": -9,
        }
        es = cma.CMAEvolutionStrategy(x0, self.sigma0, opts)
        evals: list[_Eval] = []
        evaluations = renders = gen = 0
        while not es.stop():
            xs = es.ask()
            batch = []
            for i, x in enumerate(xs):
                values = {p.name: p.value(u) for p, u in zip(self.parameters, x, strict=True)}
                e = _Eval(len(evals) + i, gen, i, values, True, 0.0, {})
                try:
                    e.measured = self.constraints.measure(stone_mesh(self.candidate_stone(values)))
                    buildable = True
                except InputError:  # e.g. a GemCAD tier re-cut until its facets vanish: no stone
                    e.measured = {k: float("nan") for k in ("depth", "table", "weight_retention")}
                    buildable = False
                key = self._key(values)
                if key in journal:
                    self._from_row(journal[key], e)
                else:
                    e.violation = self.constraints.violation(e.measured) if buildable else 1.0
                    e.feasible = e.violation == 0.0
                batch.append(e)
            need = sum(1 for e in batch if e.feasible and math.isnan(e.objective))
            prior = sum(1 for e in batch if e.feasible and self._key(e.values) in journal)
            if evaluations + prior + need > self.budget:
                break
            renders += self._evaluate_generation(gen, batch)
            for e in batch:
                if self._key(e.values) not in journal:
                    self._journal(e)
                if e.feasible:
                    evaluations += 1
            evals.extend(batch)
            try:
                es.tell(xs, [-e.objective if e.feasible else 1.0 + e.violation for e in batch])
            except ValueError:
                # cma gives up on its own terms (e.g. every candidate equally infeasible, so that
                # its step sizes collapse): the search ends here and _finish says what was found
                break
            gen += 1
            if gen > 20 * self.budget:  # every candidate infeasible for this long: give up
                break
        return self._finish(evals, evaluations, renders, gen)

    # -- outputs ---------------------------------------------------------------------------------

    def _finish(self, evals: list[_Eval], evaluations: int, renders: int, generations: int) -> dict:
        from ..atomic import atomic_path
        from ..geometry import gemcad
        from ..materials import material_from_spec

        feasible = [e for e in evals if e.feasible]
        if not feasible:
            seen = []
            for name in ("depth", "table", "weight_retention"):
                xs = [e.measured[name] for e in evals if math.isfinite(e.measured.get(name, math.nan))]
                if xs:
                    seen.append(f"{name} {min(xs):.3f} to {max(xs):.3f}")
            asked = {k: v for k, v in asdict(self.constraints).items() if v is not None}
            raise InputError(
                f"no candidate of {len(evals)} met the constraints {asked} (measured: "
                + (", ".join(seen) or "no candidate could be built")
                + "): widen the parameter bounds or the constraints",
                field="constraints",
            )
        best = max(feasible, key=lambda e: e.objective)
        stone = self.candidate_stone(best.values)
        mesh = stone_mesh(stone)
        design = mesh.metadata.get("design")
        if design is not None and "material" not in stone:
            n_d = float(design.refractive_index)  # a GemCAD stone renders with its design's index
        else:
            mat = material_from_spec(stone.get("material", "diamond"))
            n_d = float(np.real(np.asarray(mat.n(np.array([589.3])))).ravel()[0])  # type: ignore[attr-defined]
        files = {"journal": self.journal_path, "best": self.out_dir / "best.asc"}
        title = (
            "warpoptics cut optimizer: "
            + ", ".join(f"{k} {v:.3f}" for k, v in best.values.items())
            + f"; objective {best.objective:.4f}"
        )
        if design is not None:  # a GemCAD stone: its (re-cut) design, names and records kept
            design = dataclasses.replace(design, headers=[title, *design.headers], refractive_index=n_d)
            gemcad.write(design, files["best"])
        else:
            gemcad.write(mesh, files["best"], refractive_index=n_d, title=title)
        per_eval = renders_per_job(
            protocol_sweep(self.stone, self.protocol, fire=self.fire, frame_mm=self.frame_mm)
        )
        summary = {
            "best": {
                "values": best.values,
                "objective": best.objective,
                "metrics": best.metrics,
                "measured": best.measured,
            },
            "evaluations": evaluations,
            "infeasible": len(evals) - len(feasible),
            "generations": generations,
            "renders_per_evaluation": per_eval,
            "renders": evaluations * per_eval,
            "renders_this_run": renders,
            "settings": self.settings(),
        }
        files["json"] = self.out_dir / "report.json"
        write_text_atomic(files["json"], json.dumps(summary, indent=1, default=repr) + "\n")

        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 3.4))
        xs = [e.index for e in feasible]
        ys = [e.objective for e in feasible]
        ax.plot(xs, ys, "o", ms=3, color="0.5", label="candidate")
        ax.plot(xs, np.maximum.accumulate(ys), "-", color="C3", label="best so far")
        ax.set_xlabel("evaluation")
        ax.set_ylabel("objective J")
        ax.set_title("CMA-ES: " + " + ".join(f"{w:g}·{k}" for k, w in self.objective.items()), fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        files["trace"] = self.out_dir / "trace.png"
        with atomic_path(files["trace"]) as tmp:
            fig.savefig(tmp, dpi=100)
        plt.close(fig)
        if len(self.parameters) == 2:
            pa, pb = self.parameters
            fig, ax = plt.subplots(figsize=(4.8, 4.0))
            bad = [e for e in evals if not e.feasible]
            if bad:
                ax.plot([e.values[pa.name] for e in bad], [e.values[pb.name] for e in bad], "x", color="0.6")
            sc = ax.scatter(
                [e.values[pa.name] for e in feasible], [e.values[pb.name] for e in feasible], c=ys, s=14
            )
            ax.plot([best.values[pa.name]], [best.values[pb.name]], "*", ms=14, color="C3")
            ax.set_xlim(pa.low, pa.high)
            ax.set_ylim(pb.low, pb.high)
            ax.set_xlabel(pa.name)
            ax.set_ylabel(pb.name)
            fig.colorbar(sc, label="objective J")
            fig.tight_layout()
            files["parameters"] = self.out_dir / "parameters.png"
            with atomic_path(files["parameters"]) as tmp:
                fig.savefig(tmp, dpi=100)
            plt.close(fig)
        lines = [
            "# Cut optimizer report",
            "",
            f"Objective J = {' + '.join(f'{w:g} x {k}' for k, w in self.objective.items())} under the "
            f"protocol (tilts {list(self.protocol.tilts)}, azimuths {list(self.protocol.azimuths)}, "
            f"{self.protocol.lighting}, head {self.protocol.head_radius_deg:g} deg, "
            f"{self.protocol.size} px).",
            "",
            "| | " + " | ".join(p.name for p in self.parameters) + " | J |",
            "|---|" + "---|" * (len(self.parameters) + 1),
            "| start | "
            + " | ".join(f"{p.start:.3f}" for p in self.parameters)
            + f" | {feasible[0].objective:.4f} (first candidate) |",
            "| best | "
            + " | ".join(f"{best.values[p.name]:.3f}" for p in self.parameters)
            + f" | {best.objective:.4f} |",
            "",
            "Best metrics: " + ", ".join(f"{k} {v:.4f}" for k, v in best.metrics.items()),
            f"Best geometry: depth {best.measured['depth']:.3f}, table {best.measured['table']:.3f}, "
            f"weight retention {best.measured['weight_retention']:.3f}",
            "",
            f"{evaluations} evaluations ({len(evals) - len(feasible)} infeasible, not rendered) in "
            f"{generations} generations, {evaluations * per_eval} renders ({per_eval} per evaluation).",
            "",
            "Files: `best.asc` (GemCAD), `journal.csv`, `trace.png`"
            + (", `parameters.png`" if "parameters" in files else "")
            + ", `report.json`, `generations/` (one sweep per generation).",
            "",
        ]
        files["report"] = self.out_dir / "report.md"
        write_text_atomic(files["report"], "\n".join(lines))
        return {**summary, "files": files, "trace": [(e.index, e.objective) for e in feasible]}
