"""results.csv and the output folder's files: rows, atomic writes, append-only journal, job keys.

Only the runner writes the output folder.  ``results.csv`` is an append-only journal: each
finished job's row is appended, flushed and fsynced, so a killed run loses at most the jobs in
flight, and :func:`read_results` drops a torn last line.  Every other file is written atomically
(a temporary file renamed into place).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = [
    "format_value",
    "job_key",
    "image_path",
    "csv_line",
    "read_results",
    "append_line",
    "write_text_atomic",
]


def format_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (int, str)):
        return str(v)
    return json.dumps(v, sort_keys=True)


def job_key(index: int, blob: str) -> str:
    """A job's key in results.csv and in file names: its index (job order) and a hash of
    everything that determines its images (``blob``), so that a resumed run never takes a row
    rendered from another definition for this job."""
    return f"{index:04d}_{hashlib.sha1(blob.encode()).hexdigest()[:10]}"


def image_path(out_dir: Path, sweep, job, view: str, ext: str) -> Path:
    """Where a job's image of ``view`` goes: ``images/<key>.<ext>`` for the first view,
    ``images/<key>.<view>.<ext>`` for the others."""
    first = sweep.views[0].name
    name = job.key if view == first else f"{job.key}.{view}"
    return Path(out_dir) / "images" / f"{name}.{ext}"


def csv_line(values: Sequence) -> str:
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
    try:
        lines = list(reader)
    except csv.Error as exc:  # NUL bytes, a field over the csv module's size limit
        from ..errors import InputError

        raise InputError(
            f"not a results table written by warpoptics (CSV line {reader.line_num}: {exc}); "
            "use --overwrite or another folder",
            file=str(p),
        ) from None
    if not lines:
        return None, []
    header, rows = lines[0], []
    for ln in lines[1:]:
        if len(ln) == len(header):
            rows.append(dict(zip(header, ln, strict=True)))
    return header, rows


def append_line(path: Path, line: str) -> None:
    """Append one row and fsync it.  A failed append (a full disk) may leave a partial last line,
    which :func:`read_results` ignores and ``repair`` cuts; it is an :class:`OutputError`."""
    from ..errors import OutputError

    try:
        with open(path, "a", encoding="utf-8") as f:  # not-a-replace: append-only journal, fsync per row
            f.write(line)
            f.flush()
            os.fsync(f.fileno())
    except OSError as exc:
        raise OutputError(path, exc.strerror or str(exc)) from exc


def write_text_atomic(path: Path, text: str) -> None:
    from ..atomic import atomic_path

    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
