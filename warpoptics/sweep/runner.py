"""The sweep runner: the job function, the job loop over a backend, resume, and the outputs.

:func:`run_job` renders and measures one job (in this process, a pool worker or a Dask worker)
and writes nothing.  :class:`SweepRunner` owns the output folder: it writes ``sweep.json``,
appends each finished job's row to ``results.csv`` (and its EXR + PNG), skips on ``resume`` the
jobs whose rows are there, and at the end rewrites ``results.csv`` in job order and writes the
report (:mod:`warpoptics.sweep.report`).
"""

from __future__ import annotations

import contextlib
import json
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from .backends import LostJob, dask_results, local_results, pool_results
from .report import write_contact_sheet, write_pairs, write_plots, write_summary
from .results import append_line, csv_line, format_value, image_path, read_results, write_text_atomic
from .spec import METRICS, Job, Sweep, scene_for, view_settings

__all__ = ["run_job", "nondispersive", "SweepRunner", "SweepResult", "MAX_WORKERS"]

MAX_WORKERS = 256  # jobs at once on this machine (as `grade --workers`)


def nondispersive(scene):
    """``scene`` with every object's material replaced by a dispersion-free one: a constant index
    equal to the material's (ordinary) n at 589.3 nm, no absorption.  Rendered with the same
    per-pixel camera samples (wavelengths, jitter), it is the baseline of ``fire_excess``:
    colour that sampling alone puts on small bright features cancels in the difference."""
    from ..materials import material_from_spec

    ov = {}
    for i, ob in enumerate(scene.objects):
        mat = material_from_spec(ob.material)
        n_d = float(np.real(np.asarray(mat.n(np.array([589.3])))).ravel()[0])  # type: ignore[attr-defined]
        ov[f"object.{i}.material"] = {"cauchy": [n_d]}
    return scene.with_overrides(ov)


def _render(scene, device, threads):
    from ..pipelines.render import Renderer

    return Renderer(scene, device=device).run(threads=threads)


def run_job(payload: dict) -> dict:
    """Render and measure one job.  ``payload``: ``scene_data``, ``scene_path``, ``sweep_dir``,
    ``job`` (a :class:`Job` as a dict), ``views`` (view settings), ``device``, ``threads``.
    Returns ``{"key", "index", "metrics": {column: value}, "images": {view: arrays}, "rays",
    "seconds"}``; writes nothing (the runner owns the output folder)."""
    from .. import metrics as wm
    from ..grading import performance as grading_performance

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
            elif m == "contrast":
                vals["contrast"] = grading_performance.contrast(img.xyz, img.alpha)
            elif m == "extinction":
                vals["extinction"] = grading_performance.extinction(img.xyz, img.alpha, white_y=vs["white_y"])
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


@dataclass
class SweepResult:
    """What a run produced: rows of results.csv (job order), pair rows, the output paths, and
    the jobs of this run that no worker finished (``failed``: (job, reason) pairs, e.g. a pool
    worker killed by the out-of-memory killer twice)."""

    out_dir: Path
    jobs: list[Job]
    rows: list[dict]
    pairs: list[dict]
    rendered: int
    files: dict[str, Path]
    failed: list[tuple[Job, str]] = field(default_factory=list)

    @property
    def complete(self) -> bool:
        return len(self.rows) == len(self.jobs)

    def report(self) -> str:
        """One paragraph: rows done, rows failed and why, where the results are."""
        done, total = len(self.rows), len(self.jobs)
        where = self.files.get("results", self.out_dir / "results.csv")
        text = f"{done} of {total} rows done ({self.rendered} rendered in this run); results in {where}"
        if "summary" in self.files:
            text += f", summary in {self.files['summary']}"
        text += "."
        if self.failed:
            shown = "; ".join(f"job {j.index} ({j.label or j.key}): {why}" for j, why in self.failed[:5])
            more = f"; and {len(self.failed) - 5} more" if len(self.failed) > 5 else ""
            text += f" {len(self.failed)} failed: {shown}{more}."
        if done < total:
            missing = total - done - len(self.failed)
            if missing > 0:
                text += f" {missing} not run."
            text += (
                " The missing rows have no plots or summary yet: run again with --resume to render only them."
            )
        return text


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
        if not 1 <= workers <= MAX_WORKERS:  # each a process that loads Warp and renders
            raise InputError("out of range", field="--workers", value=workers, allowed=f"1 to {MAX_WORKERS}")
        if executor not in ("process", "thread"):
            raise InputError("unknown executor", field="executor", value=executor, allowed="process, thread")
        if scheduler and dask_local:
            raise InputError("give either --scheduler or --dask-local", field="--scheduler")
        if dask_local is not None and not 1 <= dask_local <= MAX_WORKERS:  # a process each, too
            raise InputError(
                "out of range", field="--dask-local", value=dask_local, allowed=f"1 to {MAX_WORKERS}"
            )
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
        return image_path(self.out_dir, self.sweep, job, view, ext)

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
            self._check_identity()
            done = self._prepare_results(header, jobs)
            write_text_atomic(
                self.out_dir / "sweep.json",
                json.dumps(
                    {
                        "identity": sw.identity(),
                        "name": sw.name,
                        "description": sw.description,
                        "source": sw.source,
                        "mode": sw.mode,
                        "axes": [{"name": a.name, "path": a.path, "values": list(a.values)} for a in sw.axes],
                        "views": [view_settings(v) for v in sw.views],
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
            self._failed: list[tuple[Job, str]] = []  # jobs no worker finished (backends.LostJob)
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

    def _check_identity(self) -> None:
        """Refuse to resume in a folder that holds another sweep's results (its ``sweep.json``
        names another identity): its rows would be mixed with or replaced by this one's."""
        meta = self.out_dir / "sweep.json"
        if self.overwrite or not self.results_path.is_file() or not meta.is_file():
            return
        try:
            old = json.loads(meta.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            old = {}
        theirs = old.get("identity") if isinstance(old, dict) else None
        if theirs is not None and theirs != self.sweep.identity():
            raise InputError(
                f"this folder holds the results of another sweep ({old.get('name')!r} from "
                f"{old.get('source')}; this is {self.sweep.name!r} from {self.sweep.source}): use "
                "another folder, or --overwrite to replace them",
                file=str(self.out_dir),
            )

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
            write_text_atomic(path, csv_line(header))
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
            "views": [view_settings(v) for v in self.sweep.views],
            "device": self.device,
            "threads": threads,
        }

    def _execute(self, pending: list[Job], header: list[str], done: int, total: int) -> int:
        if not pending:
            return 0
        data, path, _ = self.sweep.scene_source()
        from ..device import cpu_threads

        parallel = self.dask_local or (1 if self.scheduler else self.workers)
        threads = self.threads or (max(1, cpu_threads() // parallel) if parallel > 1 else None)
        payloads = [self._payload(j, data, path, threads) for j in pending]
        by_key = {j.key: j for j in pending}
        results: Iterator[dict | LostJob]
        if self.scheduler or self.dask_local:
            results = dask_results(run_job, payloads, scheduler=self.scheduler, dask_local=self.dask_local)
        elif self.workers > 1:
            results = pool_results(run_job, payloads, self.workers, self.executor)
        else:
            results = local_results(run_job, payloads)
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
                if isinstance(res, LostJob):
                    self._failed.append((by_key[res.key], res.reason))
                    continue
                self._record(by_key[res["key"]], res, header)
                n += 1
                if bar is not None:
                    bar.update(1)
        finally:
            if bar is not None:
                bar.close()
            with contextlib.suppress(Exception):
                results.close()  # type: ignore[attr-defined]  # a generator or a Dask iterator
        return n

    def _record(self, job: Job, res: dict, header: list[str]) -> None:
        from ..film.image import Image

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
        append_line(
            self.results_path,
            csv_line([format_value(row[h]) if not isinstance(row[h], str) else row[h] for h in header]),
        )

    # -- outputs -----------------------------------------------------------------------------

    @property
    def archive_path(self) -> Path:
        return self.out_dir / "archive.csv"

    def _archive(self, header: list[str], rows: list[dict]) -> int:
        """Move finished rows that are no job of this definition (values removed from an axis, a
        file the scene names replaced, a changed setting) to ``archive.csv``, never deleting one.
        Returns how many rows the archive holds."""
        old_header, kept = read_results(self.archive_path)
        if old_header is not None and old_header != header:
            # the archive of an earlier definition with other columns: keep it under its own name
            n = 1
            while (self.out_dir / f"archive.{n}.csv").exists():
                n += 1
            (self.archive_path).rename(self.out_dir / f"archive.{n}.csv")
            kept = []
        have = {r["key"] for r in kept}
        merged = kept + [r for r in rows if r["key"] not in have]
        if merged:
            text = csv_line(header) + "".join(csv_line([r[h] for h in header]) for r in merged)
            write_text_atomic(self.archive_path, text)
        return len(merged)

    def _finalize(self, jobs: list[Job], header: list[str], rendered: int) -> SweepResult:
        _h, rows = read_results(self.results_path)
        by_key: dict[str, dict] = {}
        for r in rows:
            by_key.setdefault(r["key"], r)
        ordered = [by_key[j.key] for j in jobs if j.key in by_key]
        keys = {j.key for j in jobs}
        stale = [r for k, r in by_key.items() if k not in keys]
        # the archive first: a kill between the two writes leaves a row in both, never in neither
        archived = self._archive(header, stale) if stale or self.archive_path.is_file() else 0
        text = csv_line(header) + "".join(csv_line([r[h] for h in header]) for r in ordered)
        write_text_atomic(self.results_path, text)
        files = {"results": self.results_path}
        if archived:
            files["archive"] = self.archive_path
        complete = len(ordered) == len(jobs)
        pairs = write_pairs(self.sweep, self.out_dir, jobs, by_key) if complete and self.sweep.compare else []
        if pairs:
            files["pairs"] = self.out_dir / "pairs.csv"
        if complete:
            files["contact_sheet"] = write_contact_sheet(self.sweep, self.out_dir, jobs, pairs)
            files.update(write_plots(self.sweep, self.out_dir, jobs, by_key, pairs))
            files["summary"] = write_summary(
                self.sweep, self.out_dir, jobs, by_key, pairs, rendered, archived=archived, moved=len(stale)
            )
        return SweepResult(
            out_dir=self.out_dir,
            jobs=jobs,
            rows=ordered,
            pairs=pairs,
            rendered=rendered,
            files=files,
            failed=list(self._failed),
        )
