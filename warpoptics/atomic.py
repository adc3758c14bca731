"""Atomic, verified writes: every output of warpoptics (images, meshes, GemCAD files, figures,
glTF, sweep tables and reports) goes through :func:`atomic_path`, so that a full disk, a crash or a
kill never leaves a half-written file where a finished one was.

The writer writes a temporary file beside the target; on success the file is checked (it exists,
is not empty, and an optional ``verify`` callable re-opens it), flushed to the disk (``fsync`` of
the file), renamed over the target and the folder entry flushed too (``fsync`` of the folder, the
rename's durability on POSIX file systems; see the ``rename(2)`` and ``fsync(2)`` manual pages).
Any failure removes the temporary file, keeps the file that was there before and raises one
:class:`~warpoptics.errors.OutputError` naming the path the user asked for (never the hidden
temporary name).
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

from . import interrupt
from .errors import OutputError

__all__ = ["atomic_path", "check_writable", "fsync_folder"]

# free space below which a failed write is reported as a full disk
_FULL_BYTES = 1 << 20


def fsync_folder(folder: str | os.PathLike) -> None:
    """Flush a folder's entries (a rename or a new file in it) to the disk.  File systems that
    cannot fsync a folder (EINVAL, e.g. some network mounts) are left as they are."""
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError as exc:
        if exc.errno not in (errno.EINVAL, errno.ENOTSUP, errno.EBADF):
            raise
    finally:
        os.close(fd)


def _reason(exc: BaseException, tmp: str | None, dest: Path) -> str:
    """One line saying why, naming ``dest`` where the library named the temporary file, and
    saying so when the disk is (nearly) full, which libraries rarely report as such."""
    if isinstance(exc, OutputError):
        text = exc.reason
    elif isinstance(exc, OSError) and exc.strerror:
        text = exc.strerror
    else:
        text = str(exc) or type(exc).__name__
    if tmp:
        text = text.replace(tmp, str(dest)).replace(os.path.basename(tmp), dest.name)
    text = " ".join(text.split())
    code = getattr(exc, "errno", None) or getattr(exc.__cause__, "errno", None)
    if code in _NOT_SPACE:
        return text  # a read-only file system or a permission: not a full disk, whatever df says
    with contextlib.suppress(OSError):
        free = shutil.disk_usage(dest.parent).free
        if free < _FULL_BYTES and "No space left" not in text:
            text += f" (the disk is full: {free // 1024} KiB free)"
    return text


#: errors that say why a write failed on their own: never "the disk is full" beside them (a
#: read-only file system often reports no free space)
_NOT_SPACE = (errno.EROFS, errno.EACCES, errno.EPERM, errno.EISDIR, errno.ENOTDIR, errno.ENOENT)


def check_writable(path: str | os.PathLike, *, field: str | None = "-o", folder: bool = False) -> None:
    """Fail before the work, not after it, when ``path`` (a file, or with ``folder`` a folder to
    write files in) cannot be written: the folder is created if missing and a temporary file is
    made and removed there (the one test that also catches a read-only file system for root); an
    :class:`OutputError` names ``path``, ``field`` and the reason (``Read-only file system``,
    ``Permission denied``, ...)."""
    dest = Path(path)
    where = dest if folder else dest.parent
    if dest.is_dir() and not folder:
        raise OutputError(dest, "is a folder, not a file", field=field)
    try:
        where.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".warpoptics.", suffix=".probe", dir=where)
    except OSError as exc:
        raise OutputError(dest, _reason(exc, None, dest), field=field) from exc
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)


@contextlib.contextmanager
def atomic_path(
    path: str | os.PathLike,
    *,
    field: str | None = None,
    verify: Callable[[str], None] | None = None,
) -> Iterator[str]:
    """Yield a temporary path next to ``path`` (same extension); on success check, fsync and
    rename it to ``path``.

    ``verify(tmp)`` (optional) re-reads the written file and raises on a bad one.  An ``OSError``
    in the body or in any of these steps (``ENOSPC`` on a full disk, a folder in the way, a
    read-only folder) becomes an :class:`OutputError` naming ``path`` (and ``field``, e.g.
    ``"-o"``); the old file at ``path`` is kept and no temporary file is left.
    """
    dest = Path(path)
    if dest.is_dir():
        raise OutputError(dest, "is a folder, not a file", field=field)
    tmp = None
    try:
        dest.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{dest.stem}.", suffix=f".tmp{dest.suffix}", dir=dest.parent)
    except OSError as exc:
        raise OutputError(dest, _reason(exc, tmp, dest), field=field) from exc
    os.close(fd)
    # mkstemp creates 0600; give the file the permissions a plain open() would (0666 & ~umask)
    umask = os.umask(0)
    os.umask(umask)
    try:
        os.chmod(tmp, 0o666 & ~umask)
        yield tmp
        if not os.path.isfile(tmp) or os.path.getsize(tmp) == 0:
            raise OutputError(dest, "the writer produced an empty file", field=field)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)  # a delayed write error (ENOSPC, EIO) surfaces here at the latest
        finally:
            os.close(fd)
        if verify is not None:
            verify(tmp)
        interrupt.check()  # Ctrl-C that a library swallowed: keep the old file
        os.replace(tmp, dest)
        fsync_folder(dest.parent)
    except OSError as exc:  # OutputError is an OSError too
        reason = _reason(exc, tmp, dest)  # before the unlink, while a full disk is still full
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise OutputError(dest, reason, field=field) from exc
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
