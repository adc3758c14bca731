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
    metrics = ["color", "light_return"]    # color, light_return, fire, scintillation,
                                           # contrast, extinction (warpoptics.grading)
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
exp, log, log10, sin, cos, tan, asin, acos, atan, atan2, radians, degrees, and pi, e; inputs
that would hang or exhaust memory (``9**9**9``, ``[0]*10**9``, deep nesting) are refused
(:mod:`warpoptics.sweep.expressions`).

Execution (:class:`SweepRunner`): in this process (``workers=1``), in a process or thread pool,
or on a Dask cluster (``scheduler="tcp://host:port"`` or ``dask_local=N``) with the same job
function (:func:`run_job`).  Only the runner writes the output directory: each finished job's
EXR + PNG are written atomically, then its row is appended to ``results.csv`` (flushed and
fsynced), so a killed run loses at most the jobs in flight; a rerun with ``resume=True`` skips
the jobs whose rows are there (a torn last line is dropped).  Renders are deterministic (seeded
per pixel, independent of threads and tiling), so the table does not depend on the backend.
At the end: ``results.csv`` in job order, ``pairs.csv`` and difference images (with
``[compare]``), ``contact_sheet.png``, ``plots/<metric>_vs_<axis>.png`` and ``summary.md``.

The package, by topic: :mod:`~warpoptics.sweep.spec` (the TOML schema, validation, jobs),
:mod:`~warpoptics.sweep.expressions` (the per-job expression evaluator),
:mod:`~warpoptics.sweep.runner` (:class:`SweepRunner`, the job function, resume),
:mod:`~warpoptics.sweep.backends` (local, pool, Dask), :mod:`~warpoptics.sweep.results`
(results.csv, atomic writes, job keys) and :mod:`~warpoptics.sweep.report` (contact sheet,
plots, ΔE tables, summary.md).
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
