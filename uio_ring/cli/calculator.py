"""``uio-ring hermite`` and ``uio-ring smith``: a quick calculator for normal forms.

    $ uio-ring smith "[[d, 0], [0, d + 1]]"
    invariant factors: 1, d**2 + d
    S =
    [1         0]
    [0  d**2 + d]
"""

from __future__ import annotations

import argparse
from typing import Any


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


def _run_hermite(args: argparse.Namespace) -> int:
    from uio_ring.ring import PolyMatrix, hermite

    M = PolyMatrix(args.matrix, var=args.var)
    r = hermite(M)
    print(f"rank: {r.rank}   pivot columns: {', '.join(map(str, r.pivots)) or '-'}")
    print(_show("H", r.H, args.latex))
    if args.transforms:
        print(_show("U", r.U, args.latex))
        print(f"check U·M == H: {r.verify(M).ok}")
    return 0


def _run_smith(args: argparse.Namespace) -> int:
    from uio_ring.ring import PolyMatrix, smith

    M = PolyMatrix(args.matrix, var=args.var)
    s = smith(M)
    facs = ", ".join(str(f) for f in s.invariant_factors) or "(none: zero matrix)"
    print(f"invariant factors: {facs}")
    print(_show("S", s.S, args.latex))
    if args.transforms:
        print(_show("U", s.U, args.latex))
        print(_show("V", s.V, args.latex))
        print(f"check U·M·V == S: {s.verify(M).ok}")
    return 0
