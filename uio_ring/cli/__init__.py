"""The ``uio-ring`` command.

Each subcommand lives in its own module and registers itself through
``add_parser(subparsers)``; :func:`main` dispatches.  Exit codes: 0 success,
1 a structural assumption fails, 2 bad input (arguments, text, spec).
User errors print one message, no traceback (``--debug`` shows it).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from uio_ring.cli import calculator

__all__ = ["main", "build_parser"]

_COMMAND_MODULES = [calculator]

# register later subcommands here (design, check, simulate, schema)
try:  # pragma: no cover - present once the spec layer exists
    from uio_ring.cli import spec_commands

    _COMMAND_MODULES.append(spec_commands)
except ImportError:  # pragma: no cover
    pass


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="uio-ring",
        description="Exact unknown-input observers for linear systems with commensurate delays.",
    )
    parser.add_argument("--debug", action="store_true", help="show Python tracebacks")
    parser.add_argument("--version", action="version", version="%(prog)s " + _version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in _COMMAND_MODULES:
        module.add_parser(sub)
    return parser


def _version() -> str:
    from uio_ring import __version__

    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    from uio_ring.errors import NotObservableError, UioRingError

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return int(args.run(args) or 0)
    except NotObservableError as exc:
        if args.debug:
            raise
        print(f"uio-ring: {exc}", file=sys.stderr)
        return 1
    except UioRingError as exc:
        if args.debug:
            raise
        print(f"uio-ring: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
