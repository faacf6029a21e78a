"""Degree reduction before the normal forms of square matrices.

Hermite and Smith forms (and invariant factors) do not change under unimodular
row operations.  A nonsingular n×n M whose row degrees add up to more than
``deg det M`` (a product P·D·Q of high-degree factors, say) can be brought to
weak Popov form ``R = W·M`` (W unimodular, Mulders & Storjohann 2003), whose
row degrees add up to exactly ``deg det M``.  The evaluation bounds and the
elimination then work with that degree instead of the inflated one:
``hermite(M).U = hermite(R).U · W`` and likewise for Smith.

Measured (benchmarks/bench_ring.py, P·diag(1, …, δ+1, (δ+1)(δ−2))·Q of
degree 6): Hermite with U at n = 16 went from 10.8 s to 0.3 s.
"""

from __future__ import annotations

import flint

from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring._predicates import det_raw

__all__ = ["degree_reduced"]


def degree_reduced(
    a: dn.Rows, n: int, *, track: bool, det: flint.fmpq_poly | None = None
) -> tuple[dn.Rows, dn.Rows | None] | None:
    """``(R, W)`` with ``R = W·M`` in weak Popov form when that lowers the degree
    bound of M (square, nonsingular); None when M is singular or already tight.
    ``W`` is None unless ``track``; ``det`` is det M when the caller has it.
    Precondition: n ≥ 1."""
    bound = ev.minor_degree_bound(a, n, n, n)
    if det is None:
        det = det_raw(a, n)
    if det.is_zero() or bound <= det.degree():
        return None
    r = dn.copy(a)
    w = dn.identity(n) if track else None
    dn.weak_popov(r, w)
    return r, w
