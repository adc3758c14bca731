"""User-facing errors.

Every error caused by user input (a scene file, a material, a mesh, a CLI argument) is an
:class:`InputError` that names the file, the field, the value and what is allowed.  The command
line prints it on one line and exits with status 2; no traceback unless ``--debug``.
"""

from __future__ import annotations

__all__ = ["InputError", "OutputError"]

_MISSING = object()


class InputError(ValueError):
    """Bad user input, with where it came from and what would be allowed."""

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        field: str | None = None,
        value: object = _MISSING,
        allowed: str | None = None,
    ) -> None:
        self.message = message
        self.file = None if file is None else str(file)
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(str(self))

    def __str__(self) -> str:
        where = []
        if self.file:
            where.append(_printable(self.file))
        if self.field:
            where.append(_printable(self.field))
        text = ": ".join(where)
        if self.value is not _MISSING:
            text += (" = " if text else "value ") + _capped(repr(self.value))
        message = " ".join(str(self.message).split("\n"))
        text = f"{text}: {message}" if text else message
        if self.allowed:
            text += f" (allowed: {self.allowed})"
        return text


#: the most characters of a value an error message echoes (a 7.9 MB list is not a message)
VALUE_ECHO_LIMIT = 200


def _capped(text: str) -> str:
    """``text``, or its first :data:`VALUE_ECHO_LIMIT` characters and how many there were."""
    if len(text) <= VALUE_ECHO_LIMIT:
        return text
    return f"{text[: VALUE_ECHO_LIMIT - 20]}... ({len(text):,} characters)"


def _printable(name: str) -> str:
    """A file or key name as written, or quoted with escapes when it holds a newline or another
    control character (a key ``"\\n"`` must not break the one-line message)."""
    return name if name.isprintable() else repr(name)


class OutputError(OSError):
    """An output file that could not be written (a full disk, a folder in the way, no permission).

    It names the path the user asked for (and the option, e.g. ``-o``), never a temporary file;
    the file that was at that path before is kept (:func:`warpoptics.atomic.atomic_path`).
    """

    def __init__(self, path, reason: str, *, field: str | None = None) -> None:
        self.path = str(path)
        self.reason = reason
        self.field = field
        super().__init__(str(self))

    def __reduce__(self):  # picklable across process pools and Dask workers
        return (type(self), (self.path, self.reason), {"field": self.field})

    def __str__(self) -> str:
        opt = f" ({self.field})" if self.field else ""
        kept = "nothing was written there (a file already there is kept)"
        return f"cannot write {self.path}{opt}: {self.reason}; {kept}"
