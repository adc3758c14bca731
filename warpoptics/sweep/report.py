"""The sweep report: paired ΔE and difference images, the contact sheet, plots of each metric
against each axis, and ``summary.md``.  Written from the finished ``results.csv`` rows and the
saved images; every file atomically.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from .results import csv_line, format_value, image_path, write_text_atomic
from .spec import METRICS, Job

__all__ = ["write_pairs", "write_contact_sheet", "plot_columns", "write_plots", "write_summary"]

_PLOTTED_COLOR_COLUMNS = ("L", "C", "h")
_PAIR_COLUMNS = ("dE_mean", "dE_p95", "dE_max", "dE_mean_color")


def _read_xyz_alpha(sweep, out_dir, job: Job):
    from ..film.image import read_image

    px, names = read_image(image_path(out_dir, sweep, job, sweep.views[0].name, "exr"))
    idx = {n: i for i, n in enumerate(names)}
    xyz = px[..., [idx["X"], idx["Y"], idx["Z"]]].astype(np.float64)
    return xyz, px[..., idx["A"]].astype(np.float64)


def write_pairs(sweep, out_dir, jobs: list[Job], by_key: dict) -> list[dict]:
    """Paired CIEDE2000 of each job against its ``[compare]`` reference (the job that differs only
    in the compared axis): per-pixel stats, ΔE of the mean colours, a difference image per pair
    and ``pairs.csv``.  Returns the pair rows ([] when the first view saves no images)."""
    from .. import metrics as wm
    from ..film.image import write_png

    cmp = sweep.compare
    if not sweep.views[0].save:
        return []
    others = [a.name for a in sweep.axes if a.name != cmp.axis]

    def sig(j):
        return json.dumps([j.values[n] for n in others], sort_keys=True, default=repr)

    refs = {sig(j): j for j in jobs if j.values[cmp.axis] == cmp.reference}
    out = []
    for j in jobs:
        if j.values[cmp.axis] == cmp.reference or sig(j) not in refs:
            continue
        r = refs[sig(j)]
        xa, aa = _read_xyz_alpha(sweep, out_dir, j)
        xb, ab = _read_xyz_alpha(sweep, out_dir, r)
        de = wm.delta_e_image(xa, xb)
        st = wm.delta_e_stats(de, aa, ab)
        st["dE_mean_color"] = wm.delta_e_mean_color(xa, aa, xb, ab)
        diff = out_dir / "diffs" / f"{j.key}__vs__{r.key}.png"
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
                "diff_image": str(diff.relative_to(out_dir)),
            }
        )
    if out:
        hdr = list(out[0])
        write_text_atomic(
            out_dir / "pairs.csv",
            csv_line(hdr)
            + "".join(
                csv_line([format_value(p[h]) if not isinstance(p[h], str) else p[h] for h in hdr])
                for p in out
            ),
        )
    return out


def write_contact_sheet(sweep, out_dir, jobs: list[Job], pairs: list[dict]) -> Path:
    """``contact_sheet.png``: every job's first-view image, then the difference images."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..atomic import atomic_path
    from ..film.image import read_image

    tiles = []
    for j in jobs:
        p = image_path(out_dir, sweep, j, sweep.views[0].name, "png")
        tiles.append((read_image(p)[0] if p.is_file() else None, j.label))
    for pr in pairs:
        tiles.append(
            (
                read_image(out_dir / pr["diff_image"])[0],
                f"ΔE00 {pr['label']}\nmean {pr['dE_mean']:.2f}, p95 {pr['dE_p95']:.1f}",
            )
        )
    last = sweep.axes[-1]
    ncols = (
        len(last.values)
        if sweep.mode == "product" and 1 < len(last.values) <= 8
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
    fig.suptitle(sweep.name, fontsize=9)
    fig.tight_layout()
    out = out_dir / "contact_sheet.png"
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
    return out


def plot_columns(sweep) -> list[str]:
    """The results.csv columns that get plots (colour: L, C, h only)."""
    cols = []
    several = len(sweep.views) > 1
    for v in sweep.views:
        for m in v.metrics:
            for c in _PLOTTED_COLOR_COLUMNS if m == "color" else METRICS[m]:
                cols.append(f"{v.name}_{c}" if several else c)
    return cols


def write_plots(sweep, out_dir, jobs: list[Job], by_key: dict, pairs: list[dict]) -> dict[str, Path]:
    """``plots/<column>_vs_<axis>.png`` for each plotted column (and ΔE) against each axis with more
    than one value; one line per combination of the other axes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..atomic import atomic_path

    files = {}
    pair_by_key = {p["key"]: p for p in pairs}
    series = [(c, lambda j, c=c: float(by_key[j.key][c]), jobs) for c in plot_columns(sweep)]
    if pairs:
        pj = [j for j in jobs if j.key in pair_by_key]
        series += [(c, lambda j, c=c: float(pair_by_key[j.key][c]), pj) for c in ("dE_mean", "dE_mean_color")]
    for col, get, subset in series:
        for ax_def in sweep.axes:
            multi = [a for a in sweep.axes if len(a.values) > 1]
            if len(ax_def.values) < 2 or (
                pairs and col.startswith("dE") and ax_def.name == sweep.compare.axis and len(multi) > 1
            ):
                continue  # ΔE against the compared axis only when it is the only one
            numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in ax_def.values)
            others = [a for a in sweep.axes if a.name != ax_def.name and len(a.values) > 1]
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
            ax.set_title(f"{sweep.name}: {col} vs {ax_def.name}", fontsize=9)
            fig.tight_layout()
            out = out_dir / "plots" / f"{_slug(col)}_vs_{_slug(ax_def.name)}.png"
            out.parent.mkdir(parents=True, exist_ok=True)
            with atomic_path(out) as tmp:
                fig.savefig(tmp, dpi=100, format="png")
            plt.close(fig)
            files[f"plot:{col}:{ax_def.name}"] = out
    return files


def write_summary(
    sweep,
    out_dir,
    jobs: list[Job],
    by_key: dict,
    pairs: list[dict],
    rendered: int,
    *,
    archived: int = 0,
    moved: int = 0,
) -> Path:
    """``summary.md``: the run, a table of every job's plotted columns, extremes, pairs, files.
    ``archived``: rows in ``archive.csv`` (finished jobs of an earlier definition), ``moved`` of
    them in this run."""
    sw = sweep
    rows = [by_key[j.key] for j in jobs]
    cols = plot_columns(sweep)
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
    ]
    if archived:
        lines.append(
            f"- archive.csv: {archived} finished rows of earlier definitions of this sweep (values "
            f"removed or files replaced; {moved} moved there in this run), kept, not in this table"
        )
    lines += [
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
            f"## Paired differences: {cmp.axis} vs {cmp.axis} = {format_value(cmp.reference)}",
            "",
            "CIEDE2000 per pixel over the stones' pixels (mean, 95th percentile, max) and between the "
            "stones' mean colours; difference images in `diffs/` (full scale ΔE = "
            f"{cmp.scale:g}).",
            "",
            "| " + " | ".join(others + [cmp.axis]) + " | ΔE mean | ΔE p95 | ΔE max | ΔE of means | image |",
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
    out = out_dir / "summary.md"
    write_text_atomic(out, "\n".join(lines))
    return out


def _fmt_num(s) -> str:
    try:
        v = float(s)
    except (TypeError, ValueError):
        return str(s)
    return f"{v:.4g}"


def _slug(s: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", s)
