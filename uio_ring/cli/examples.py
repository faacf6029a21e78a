"""``uio-ring example``: copy a shipped example spec into the current folder.

    $ uio-ring example --list
    $ uio-ring example zheng2015          # writes ./zheng2015.yaml
    $ uio-ring design zheng2015.yaml

The examples are package data (``uio_ring/examples/*.yaml``), so they are in
every install, wheel included.  An existing file is never replaced unless
``--force`` is given (exit code 2 otherwise).
"""

from __future__ import annotations

import argparse
import difflib
import sys
from importlib import resources
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "example_names", "example_text"]


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "example",
        help="write a shipped example spec into the current folder",
        description="Write one of the example spec files shipped with uio_ring into the current "
        "folder (as NAME.yaml), to run 'uio-ring design NAME.yaml' on it or edit it. An existing "
        "file is not replaced unless --force is given. --list shows the names.",
    )
    p.add_argument("name", nargs="?", help="example name (see --list)")
    p.add_argument("--list", action="store_true", help="list the examples and what each shows")
    p.add_argument("--force", action="store_true", help="replace an existing file of the same name")
    p.set_defaults(run=_run_example)


def _folder() -> Any:
    return resources.files("uio_ring").joinpath("examples")


def example_names() -> list[str]:
    """Names of the shipped example specs (file names without ``.yaml``), sorted."""
    return sorted(f.name[: -len(".yaml")] for f in _folder().iterdir() if f.name.endswith(".yaml"))


def example_text(name: str) -> str:
    """The text of the shipped example ``name`` (``"zheng2015"`` or ``"zheng2015.yaml"``).

    Raises :class:`~uio_ring.errors.SpecError` for an unknown name, with the
    closest known one.
    """
    from uio_ring.errors import SpecError

    stem = name[: -len(".yaml")] if name.endswith(".yaml") else name
    names = example_names()
    if stem not in names:
        close = difflib.get_close_matches(stem, names, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise SpecError(f"no example named {name!r}{hint} (known: {', '.join(names)})")
    return _folder().joinpath(stem + ".yaml").read_text(encoding="utf-8")


def _summary(text: str) -> str:
    """The spec's ``description``, else its first comment line."""
    import yaml

    data = yaml.safe_load(text)
    if isinstance(data, dict) and data.get("description"):
        return str(data["description"])
    for line in text.splitlines():
        if line.startswith("#"):
            return line.lstrip("# ").strip()
    return ""


def _run_example(args: argparse.Namespace) -> int:
    if args.list or args.name is None:
        if args.name is None and not args.list:
            print("uio-ring example: give a NAME (or --list); the examples are:", file=sys.stderr)
        names = example_names()
        width = max(map(len, names), default=0)
        for name in names:
            print(f"{name:<{width}}  {_summary(example_text(name))}", file=sys.stdout if args.list else sys.stderr)
        return 0 if args.list else 2
    text = example_text(args.name)
    name = args.name[: -len(".yaml")] if args.name.endswith(".yaml") else args.name
    target = Path(name + ".yaml")
    try:
        with open(target, "w" if args.force else "x", encoding="utf-8") as fh:
            fh.write(text)
    except FileExistsError:
        print(f"uio-ring: error: {target} exists; not replaced (use --force to replace it)", file=sys.stderr)
        return 2
    print(f"wrote {target}; run: uio-ring design {target}")
    return 0
