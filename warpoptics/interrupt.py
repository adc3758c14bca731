"""Ctrl-C for the ``warpoptics`` command: prompt, without a traceback, and never clobbering an
output.

Two things made Ctrl-C in the first seconds of a command fail: a ``KeyboardInterrupt``
raised inside the package's imports printed a traceback, and trimesh's optional imports catch
``BaseException`` (``trimesh.exceptions.ExceptionWrapper``) — an interrupt that lands there is
swallowed, and the render ran to the end and replaced the file the user meant to keep.  So:

- :func:`guard_startup` runs when this module is imported, first thing in
  ``warpoptics/__init__.py``, when the process is the
  command (``warpoptics ...`` or ``python -m warpoptics.cli ...``; a library user's handler is
  never touched): until the command starts, SIGINT ends the process at once with status 130
  (nothing is written during the imports, so nothing is lost).
- :func:`handling` (the command's run) makes SIGINT set a flag as well as raise
  ``KeyboardInterrupt``; :func:`warpoptics.atomic.atomic_path` checks the flag before it
  renames a finished file over an old one, so an interrupt that a library swallowed still
  keeps the old file; tiled launches check it between tiles.  A second Ctrl-C ends the process
  at once.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Iterator

__all__ = ["guard_startup", "handling", "requested", "check", "EXIT_STATUS"]

EXIT_STATUS = 130  # 128 + SIGINT, the shells' convention
_MESSAGE = b"warpoptics: interrupted\n"
_state = {"interrupted": False}


def _is_command() -> bool:
    argv = list(getattr(sys, "orig_argv", sys.argv))
    if "-m" in argv:
        i = argv.index("-m")
        return argv[i + 1 : i + 2] == ["warpoptics.cli"]
    return bool(sys.argv) and os.path.basename(sys.argv[0]) in ("warpoptics", "warpoptics.exe")


def _exit_now(signum, frame) -> None:  # pragma: no cover - ends the process
    os.write(2, _MESSAGE)
    os._exit(EXIT_STATUS)


def guard_startup() -> None:
    """While the command imports, make SIGINT end it at once (status 130, one line)."""
    if threading.current_thread() is not threading.main_thread() or not _is_command():
        return
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _exit_now)


def _raise(signum, frame) -> None:
    if _state["interrupted"]:
        _exit_now(signum, frame)  # the second Ctrl-C: the user insists
    _state["interrupted"] = True
    raise KeyboardInterrupt


def requested() -> bool:
    """True once Ctrl-C was pressed during :func:`handling` (even if a library swallowed it)."""
    return _state["interrupted"]


def check() -> None:
    """Raise ``KeyboardInterrupt`` if Ctrl-C was pressed (a checkpoint between units of work)."""
    if _state["interrupted"]:
        raise KeyboardInterrupt


@contextlib.contextmanager
def handling() -> Iterator[None]:
    """Within: SIGINT raises ``KeyboardInterrupt`` and sets :func:`requested`; the previous
    handler and a clear flag are restored after (so that in-process callers, tests, are left as
    they were)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, _raise)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        _state["interrupted"] = False


guard_startup()
