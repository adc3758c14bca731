"""The ``warpoptics`` command.

Subcommands live next to the code they drive; each such module defines
``register(subparsers)`` which adds its parser and sets ``func`` on it.  Add new modules to
``SUBCOMMAND_MODULES``.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

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


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    # --debug is a global option, but users also type it after the subcommand
    debug = "--debug" in argv
    if debug and argv.index("--debug") > 0:
        argv.remove("--debug")
        argv.insert(0, "--debug")
    args = parser.parse_args(argv)
    if args.device:
        os.environ["WARPOPTICS_DEVICE"] = args.device
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with interrupt.handling():
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
