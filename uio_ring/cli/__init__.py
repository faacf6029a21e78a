"""The ``uio-ring`` command.

Each subcommand lives in its own module and registers itself through
``add_parser(subparsers)``; :func:`main` dispatches.  Exit codes: 0 success,
1 a structural assumption fails (or a certificate fails), 2 bad input
(arguments, text, spec, output folder), 130 interrupted (Ctrl-C; nothing
half-written remains).  User errors print one message, no traceback
(``--debug`` adds it, with the same exit code).  When the reader of standard
output goes away (``uio-ring design spec.yaml | head``) the command stops
quietly with exit code 141, as a process ended by SIGPIPE does in a shell.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from collections.abc import Sequence

from uio_ring.cli import calculator, examples

__all__ = ["main", "build_parser"]

_COMMAND_MODULES = [calculator, examples]

# register later subcommands here (design, check, simulate, schema)
try:  # pragma: no cover - present once the spec layer exists
    from uio_ring.cli import spec_commands

    _COMMAND_MODULES.append(spec_commands)
except ImportError:  # pragma: no cover
    pass

from uio_ring.cli import sweep_command  # noqa: E402

_COMMAND_MODULES.append(sweep_command)


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
    try:
        code = _dispatch(argv)
        sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
    except BrokenPipeError:
        _discard_stdout()
        return _EXIT_BROKEN_PIPE
    return code


#: exit code when standard output is closed early (128 + SIGPIPE, as a shell reports it)
_EXIT_BROKEN_PIPE = 141


def _discard_stdout() -> None:
    """Point stdout at /dev/null so the interpreter's final flush does not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # stdout without a file descriptor (tests)
        pass


def _dispatch(argv: Sequence[str] | None) -> int:
    from uio_ring.errors import NotObservableError, UioRingError

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return int(args.run(args) or 0)
    except NotObservableError as exc:
        _report(exc, args.debug, f"uio-ring: {exc}")
        return 1
    except UioRingError as exc:
        _report(exc, args.debug, f"uio-ring: error: {_one_line(str(exc))}")
        return 2
    except KeyboardInterrupt as exc:
        _report(exc, args.debug, "uio-ring: interrupted")
        return 130


def _one_line(text: str, limit: int = 500) -> str:
    text = " ".join(text.split("\n"))
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _report(exc: BaseException, debug: bool, message: str) -> None:
    """One line on stderr; with ``--debug`` the traceback first (the exit code stays the same)."""
    if debug:
        traceback.print_exception(exc, file=sys.stderr)
    print(message, file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
