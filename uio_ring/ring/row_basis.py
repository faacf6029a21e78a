"""Growing a row module one block at a time: reduce the new rows modulo a weak Popov basis.

Given a basis B of a row module in weak Popov form (distinct leading positions) and
new rows X, :func:`extend_row_basis` returns

* ``rows``  — X reduced modulo L(B): every operation is ``x ← x − c·δ^e·b`` for a
  basis row b whose leading position is that of x and whose degree there is at most
  that of x; rows that become zero are dropped and each remaining row is scaled to a
  primitive integer row (a unit of Q[δ]).  So ``L(B) + L(rows) = L(B) + L(X)``.
  The steps run fraction-free on integer rows (each one the rational step times a
  positive integer, contents divided out), which gives the same primitive rows;
* ``basis`` — a weak Popov basis of that sum (Mulders & Storjohann 2003), or I when
  the sum is proved to be all of Q[δ]^n (two coprime compressed maximal minors modulo a
  prime, or exactly when cheap: :func:`_spans_everything`).  The
  Mulders–Storjohann sequence can swell by hundreds of bits a step where the new rows
  are large: for a random 8-state spec with 8 outputs at δ-degree 16, a 12×8 of
  2.6-kbit rows ran for minutes; the proof takes 12 ms.

Degrees: the module ``L(B) + L(X)`` has a basis whose row degrees add up to the
largest degree of its maximal minors; the reduction keeps the new rows near that
instead of letting them grow with every product.  Each step lowers the pair
(degree, leading position) of x, so the loop ends after at most ``n·(deg x + 1)``
steps, each O(n) polynomial products.

The analysis uses it for the rows ``Δ_k`` of algorithm (4)–(5)
(:mod:`uio_ring.analysis.observability`), whose raw degrees grow by the degree of
the Hermite transforms at every step.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> ext = extend_row_basis(PolyMatrix("[[1, d]]"), PolyMatrix("[[d, d**2 + 1], [2, 2*d]]"))
>>> ext.rows, ext.basis
(PolyMatrix([[0, 1]]), PolyMatrix([[1, 0], [0, 1]]))
"""

from __future__ import annotations

from dataclasses import dataclass

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _division as dv
from uio_ring.ring._predicates import coprime_maximal_minors, minors_work
from uio_ring.ring.errors import DimensionError
from uio_ring.ring.matrix import PolyMatrix, require_matrix

__all__ = ["RowBasisExtension", "extend_row_basis", "is_weak_popov", "remainder_rows"]


@dataclass(frozen=True)
class RowBasisExtension:
    """``rows``: the new rows reduced modulo the old basis (zero rows dropped), with
    ``L(old) + L(rows) = L(old) + L(new)``; ``basis``: a weak Popov basis of that module."""

    rows: PolyMatrix
    basis: PolyMatrix


def is_weak_popov(B: PolyMatrix) -> bool:
    """True if B has no zero row and its rows have distinct leading positions (row-wise,
    zero shift: the rightmost entry of largest degree).

    >>> is_weak_popov(PolyMatrix("[[1, d], [d, 1]]")), is_weak_popov(PolyMatrix("[[1, d], [0, d]]"))
    (True, False)
    """
    B = require_matrix(B, "is_weak_popov")
    lead = [dn.leading_position(r)[1] for r in B._r]
    return all(j >= 0 for j in lead) and len(set(lead)) == len(lead)


def _content(row: list[flint.fmpz_poly]) -> flint.fmpz:
    """The gcd of all coefficients of an integer row (0 for a zero row)."""
    content = flint.fmpz(0)
    for p in row:
        if not p.is_zero():
            content = content.gcd(p.content())
            if content == 1:
                break
    return content


_CONTENT_EVERY = 4  # steps between content removals (any value ≥ 1 gives the same rows)


def _reduce_row(x: list[flint.fmpq_poly], lead: dict[int, list[flint.fmpz_poly]]) -> list[flint.fmpq_poly]:
    """x minus basis rows until its leading term is no longer divisible (see the module
    docstring), as a primitive integer row ([] when x reduces to zero).

    Fraction-free: with x and the basis rows scaled to integer rows, the rational step
    ``x ← x − (lc x / lc b)·δ^e·b`` is replaced by ``x ← a·x − c·δ^e·b`` with
    ``a = lc b / g > 0``, ``c = ± lc x / g``, ``g = gcd(lc b, lc x)`` — the same row
    times the positive integer a — and the content of x is divided out every few
    steps.  The result is therefore a positive rational multiple of the rational
    reduction's, and after scaling to a primitive integer row it is the same row.
    Rational arithmetic put a growing common denominator on every step (4–5× slower on
    random 8-state systems of δ-degree 16, with 1–6 kbit coefficients).
    Precondition: ``lead`` maps distinct leading positions to integer basis rows.
    """
    # Invariant: z = (positive rational)·(x − Σ q_i b_i); (deg, position) decreases.
    z, _ = bk.integer_row(x)
    steps = 0
    while True:
        d, j = dn.leading_position(z)
        if j < 0:
            return []
        b = lead.get(j)
        if b is None or b[j].degree() > d:
            break
        lb, lx = b[j][b[j].degree()], z[j][d]
        g = lb.gcd(lx)
        a, c = lb // g, lx // g
        if a < 0:
            a, c = -a, -c
        e = d - b[j].degree()
        # (c·bi).left_shift(e) = c·δ^e·bi; a product with the monomial polynomial costs a full multiplication
        z = [a * zi - (c * bi).left_shift(e) if not bi.is_zero() else a * zi for zi, bi in zip(z, b, strict=True)]
        steps += 1
        if steps % _CONTENT_EVERY == 0:
            content = _content(z)
            if content > 1:
                z = [p // content for p in z]
    content = _content(z)
    return [bk.from_integer(p // content) for p in z]


def remainder_rows(rows: PolyMatrix, basis: PolyMatrix) -> PolyMatrix:
    """Each row x of ``rows`` reduced modulo L(basis): its Popov normal form ``x − q·P``,
    P the Popov form of the weak Popov ``basis`` (same module, same pivot positions and
    degrees), every entry of a pivot column below that pivot's degree.  Unique, and
    ``x − (result) ∈ L(basis)`` exactly, with no unit factor (the rows keep their rational
    scale, unlike :func:`extend_row_basis`): for callers that need that.

    Algorithm: one matrix division by P (:func:`~uio_ring.ring._division.reduce_modulo_popov`;
    the quotient is the polynomial part of ``x_π·P_π⁻¹``, P_π the pivot columns) — k² + k·n
    products per row instead of one pass over the row per removed leading term.  On the
    w-step of a random 8-state spec with 8 outputs at δ-degree 16 (4 rows of degree 62 with
    6.2-kbit coefficients modulo a basis of degree 32): 0.43 s against 21 s for the
    leading-term reduction of earlier versions, which gave the same rows there.
    Precondition: ``basis`` is in weak Popov form (not checked).

    >>> remainder_rows(PolyMatrix("[[d, d**2 + 1]]"), PolyMatrix("[[0, d]]"))
    PolyMatrix([[d, 1]])
    >>> remainder_rows(PolyMatrix("[[d**3, 2*d**2]]"), PolyMatrix("[[2*d, 1]]"))
    PolyMatrix([[0, 3*d**2/2]])
    """
    if not basis.rows:
        return PolyMatrix._new(dn.copy(rows._r), rows.rows, rows.cols, rows.var)
    popov = dn.copy(basis._r)
    dn.popov(popov)
    out = dv.reduce_modulo_popov(rows._r, popov)
    return PolyMatrix._new(out, rows.rows, rows.cols, rows.var)


#: The largest n⁵·deg·bits of the stacked rows for which :func:`_spans_everything` completes a
#: failed modular proof by exact minors (about a second at most; the attempt is speculative:
#: a proper submodule pays it for nothing).
EXACT_PROOF_BUDGET = 10**9


def _spans_everything(rows: dn.Rows, n: int) -> bool:
    """True when the tall stacked rows are proved to span Q[δ]^n: two coprime compressed
    maximal minors (:func:`~uio_ring.ring._predicates.coprime_maximal_minors`), modulo a
    prime, or exactly within ``EXACT_PROOF_BUDGET`` (a 13×8 of degree 38 with 276-bit rows
    misses the modular proof: not column reduced; its Mulders–Storjohann sequence took 28 s
    and ended in a constant matrix of 88-kbit entries; the exact minors take 0.1 s).  Tall
    only: a square matrix's compressed minors are det M times constants, and their mixed
    rows take every row to the largest degree (a 16×16 of row degrees 16 … 320: 2.6 s for
    no proof, where the reduction takes less)."""
    m = len(rows)
    if m <= n:
        return False
    return coprime_maximal_minors(rows, m, n, exact=minors_work(rows, n) <= EXACT_PROOF_BUDGET)


def extend_row_basis(basis: PolyMatrix, rows: PolyMatrix) -> RowBasisExtension:
    """Reduce ``rows`` modulo the weak Popov ``basis`` and extend the basis (module docstring).

    Parameters
    ----------
    basis
        k×n in weak Popov form (:func:`is_weak_popov`; k = 0 allowed).
    rows
        r×n, the rows to add.

    Returns
    -------
    RowBasisExtension
        ``rows`` (r'×n, r' ≤ r) and ``basis`` (weak Popov, k'×n) with
        ``L(basis) + L(rows) = L(basis) + L(new basis) = L(old basis) + L(given rows)``.

    Raises
    ------
    DimensionError
        If the column counts differ or ``basis`` is not in weak Popov form.
    """
    basis = require_matrix(basis, "extend_row_basis")
    rows = require_matrix(rows, "extend_row_basis")
    n = basis.cols
    if rows.cols != n:
        raise DimensionError(f"extend_row_basis: rows have {rows.cols} columns; expected {n} (= basis)")
    if basis.rows and not is_weak_popov(basis):
        raise DimensionError("extend_row_basis: the basis is not in weak Popov form")
    lead = {dn.leading_position(r)[1]: bk.integer_row(r)[0] for r in basis._r}
    reduced = [_reduce_row(list(r), lead) for r in rows._r]
    reduced = [r for r in reduced if r]
    new = dn.copy(basis._r) + dn.copy(reduced)
    if _spans_everything(new, n):
        new = dn.identity(n)  # the module is Q[δ]^n: I is its basis
    else:
        kept = dn.weak_popov(new)
        new = new[: len(kept)]
    return RowBasisExtension(
        rows=PolyMatrix._new(reduced, len(reduced), n, basis.var),
        basis=PolyMatrix._new(new, len(new), n, basis.var),
    )
