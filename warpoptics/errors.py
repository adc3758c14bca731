"""User-facing errors.

Every error caused by user input (a scene file, a material, a mesh, a CLI argument) is an
:class:`InputError` that names the file, the field, the value and what is allowed.  The command
line prints it on one line and exits with status 2; no traceback unless ``--debug``.
"""

from __future__ import annotations

__all__ = ["InputError"]

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
            where.append(self.file)
        if self.field:
            where.append(self.field)
        text = ": ".join(where)
        if self.value is not _MISSING:
            text += (" = " if text else "value ") + repr(self.value)
        text = f"{text}: {self.message}" if text else self.message
        if self.allowed:
            text += f" (allowed: {self.allowed})"
        return text
