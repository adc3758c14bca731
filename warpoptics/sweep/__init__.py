"""Parameter sweeps: a base scene, axes of values addressed by dotted paths, resumable parallel runs.

A sweep renders one job per combination of axis values and measures each image with the
metrics of :mod:`warpoptics.metrics`.  It is defined in TOML (``Sweep.load``: ``name``,
``scene``, ``mode`` = "product" | "zip", ``[set]``, ``[[axis]]``, ``[expr]``, ``[[view]]``,
``[compare]``) or in Python (``Sweep(...)``).  Dotted paths are those of
``Scene.with_overrides`` (``object.0.diameter``, ``render.spp``); paths below
``object.N.material`` turn a material name into an inline table first.  Expressions are a
restricted Python (:mod:`warpoptics.sweep.expressions`) that refuses inputs that would hang or
exhaust memory.

Execution (:class:`SweepRunner`): in this process, a process or thread pool, or a Dask cluster,
with the same job function (:func:`run_job`).  Only the runner writes the output directory: each
job's EXR + PNG atomically, then its row appended to ``results.csv`` (flushed and fsynced), so a
killed run loses at most the jobs in flight and ``resume=True`` skips finished jobs.  Renders are
deterministic, so the table does not depend on the backend.  At the end: ``results.csv`` in job
order, ``pairs.csv`` and difference images (with ``[compare]``), ``contact_sheet.png``, plots
and ``summary.md``.

The file format with every key, the path and expression rules: docs/design/sweeps.md.

The package, by topic: :mod:`~warpoptics.sweep.spec` (schema, validation, jobs),
:mod:`~warpoptics.sweep.expressions`, :mod:`~warpoptics.sweep.runner` (:class:`SweepRunner`,
resume), :mod:`~warpoptics.sweep.backends` (local, pool, Dask), :mod:`~warpoptics.sweep.results`
(results.csv, job keys) and :mod:`~warpoptics.sweep.report` (contact sheet, plots, summary.md).
"""

from __future__ import annotations

from .expressions import evaluate_expression
from .results import read_results
from .runner import SweepResult, SweepRunner, run_job
from .spec import METRICS, Axis, Compare, Job, Sweep, View, apply_overrides

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
