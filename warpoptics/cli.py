"""The ``warpoptics`` command.

Subcommands live next to the code they drive; each such module defines
``register(subparsers)`` which adds its parser and sets ``func`` on it.  Add new modules to
``SUBCOMMAND_MODULES``.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import sys
import warnings

from . import interrupt
from .errors import InputError

# Modules that provide `register(subparsers)`; order = order in `warpoptics --help`.
SUBCOMMAND_MODULES = [
    "warpoptics.commands.render",
    "warpoptics.commands.view",
    "warpoptics.commands.bench",
    "warpoptics.commands.info",
    "warpoptics.commands.spectrum",
    "warpoptics.commands.material",
    "warpoptics.commands.cut",
    "warpoptics.commands.thinfilm",
    "warpoptics.commands.chart",
    "warpoptics.commands.microscope",
    "warpoptics.commands.sweep",
    "warpoptics.commands.colorchange",
    "warpoptics.commands.grade",
]


def build_parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="warpoptics",
        description="Spectral, polarized rendering and measurement of gemstones, prisms and thin films.",
    )
    parser.add_argument("--version", action="version", version=f"warpoptics {__version__}")
    parser.add_argument("--debug", action="store_true", help="show Python tracebacks on errors")
    parser.add_argument(
        "--device", default=None, help='Warp device ("cpu", "cuda:0"); default $WARPOPTICS_DEVICE or cpu'
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in SUBCOMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


@contextlib.contextmanager
def _warnings_as_lines(command: str):
    """Warnings raised while a command runs (a GemCAD design's repeated facets, ...) come out as
    one line each, ``warpoptics COMMAND: warning: ...``, and a message already shown (the same
    design read twice) is not repeated."""
    seen: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split("\n"))
        if text not in seen:
            seen.add(text)
            print(f"warpoptics {command}: warning: {text}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.simplefilter("always", UserWarning)
        warnings.showwarning = show
        yield


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    # --debug is a global option, but users also type it after the subcommand
    debug = "--debug" in argv
    if debug and argv.index("--debug") > 0:
        argv.remove("--debug")
        argv.insert(0, "--debug")
    for word in argv:
        # Python 3.11's argparse turns `--flag=--` into an empty list that skips the flag's type
        # check (a TypeError deep in the command): refuse it as argparse refuses `--flag` alone
        flag, eq, value = word.partition("=")
        if flag.startswith("-") and eq and value == "--":
            parser.error(f"argument {flag}: expected one argument, not '--'")
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with interrupt.handling(), _warnings_as_lines(args.command):
            if args.device:  # an unknown device is refused before any work (a Dask cluster, a render)
                from .device import get_device

                get_device(args.device)
                os.environ["WARPOPTICS_DEVICE"] = args.device
            result = args.func(args)
        return int(result or 0)
    except (InputError, FileNotFoundError, ValueError) as exc:
        if args.debug:
            raise
        print(f"warpoptics {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # a file that cannot be read or written: one line, no traceback
        if args.debug:
            raise
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"warpoptics {args.command}: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("warpoptics: interrupted", file=sys.stderr)
        return interrupt.EXIT_STATUS


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
