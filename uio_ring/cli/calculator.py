"""``uio-ring hermite`` and ``uio-ring smith``: a quick calculator for normal forms.

    $ uio-ring smith "[[d, 0], [0, d + 1]]"
    invariant factors: 1, d**2 + d
    S =
    [1         0]
    [0  d**2 + d]

The matrix text is bounded while it is parsed: at most ``MAX_SIZE`` rows and
columns, degree ``MAX_DEGREE`` and the spec loader's coefficient size, so a
hostile argument is refused before any work (exit 2).  At those limits a run takes
up to a minute and prints half a gigabyte with ``--transforms``; every
``HEARTBEAT_SECONDS`` a line on stderr says which step runs
(:class:`~uio_ring.cli.heartbeat.Heartbeat`).
"""

from __future__ import annotations

import argparse
from typing import Any

from uio_ring.cli.heartbeat import Heartbeat

#: Largest degree accepted by the calculator (entries and every intermediate result), as in specs.
MAX_DEGREE = 16
#: Most rows or columns accepted by the calculator.
MAX_SIZE = 16


def _matrix(text: str, var: str) -> Any:
    from uio_ring.errors import DimensionError
    from uio_ring.ring import PolyMatrix
    from uio_ring.ring.parse import parse_matrix
    from uio_ring.spec.loader import MAX_COEFFICIENT_BITS

    if len(text) > 1_000_000:
        raise DimensionError(f"the matrix text has {len(text)} characters; at most 1 000 000")
    rows = parse_matrix(text, var, max_degree=MAX_DEGREE, max_bits=MAX_COEFFICIENT_BITS)
    if len(rows) > MAX_SIZE or any(len(r) > MAX_SIZE for r in rows):
        raise DimensionError(f"the calculator takes at most {MAX_SIZE}×{MAX_SIZE} matrices")
    return PolyMatrix(rows, var=var)


def add_parser(sub: Any) -> None:
    for name, helptext in (
        ("hermite", "normalised row Hermite form H (and U with U·M = H)"),
        ("smith", "Smith form S and invariant factors (and U, V with U·M·V = S)"),
    ):
        p = sub.add_parser(name, help=helptext, description=helptext)
        p.add_argument("matrix", help='the matrix, e.g. "[[d, 1 + 2*d], [0, d**2 - 1/3]]" (δ or d)')
        p.add_argument("--var", default="d", help="name of the indeterminate (default d = δ)")
        p.add_argument("--transforms", action="store_true", help="also print the unimodular transforms")
        p.add_argument("--latex", action="store_true", help="print LaTeX instead of plain text")
        p.set_defaults(run=_run_hermite if name == "hermite" else _run_smith)


def _show(name: str, M: Any, latex: bool) -> str:
    if latex:
        return f"{name} = {M.to_latex()}"
    return f"{name} =\n{M}"


def _what(form: str, M: Any) -> str:
    return f"computing the {form} of a {M.rows}×{M.cols} matrix of δ-degree {M.degree()} (exact algebra over Q[δ])"


def _run_hermite(args: argparse.Namespace) -> int:
    from uio_ring._progress import note
    from uio_ring.ring import hermite

    M = _matrix(args.matrix, args.var)
    with Heartbeat(_what("Hermite form", M)):
        note("the form and its transform U")
        r = hermite(M)
        note("writing H")
        print(f"rank: {r.rank}   pivot columns: {', '.join(map(str, r.pivots)) or '-'}")
        print(_show("H", r.H, args.latex))
        if args.transforms:
            note(f"writing U (δ-degree {r.U.degree()})")
            print(_show("U", r.U, args.latex))
            note("checking U·M == H and that U is unimodular")
            print(f"check U·M == H: {r.verify(M).ok}")
    return 0


def _run_smith(args: argparse.Namespace) -> int:
    from uio_ring._progress import note
    from uio_ring.ring import smith

    M = _matrix(args.matrix, args.var)
    with Heartbeat(_what("Smith form", M)):
        note("the form and its transforms U, V")
        s = smith(M)
        note("writing S")
        facs = ", ".join(str(f) for f in s.invariant_factors) or "(none: zero matrix)"
        print(f"invariant factors: {facs}")
        print(_show("S", s.S, args.latex))
        if args.transforms:
            note(f"writing U and V (δ-degrees {s.U.degree()} and {s.V.degree()})")
            print(_show("U", s.U, args.latex))
            print(_show("V", s.V, args.latex))
            note("checking U·M·V == S and that U and V are unimodular")
            print(f"check U·M·V == S: {s.verify(M).ok}")
    return 0
