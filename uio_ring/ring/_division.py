"""Division with remainder by a Popov basis, in one matrix step.

For a basis P (k×m) in row-wise Popov form with pivot positions π and pivot
degrees d, and a row x, the remainder ``x − q·P`` with ``deg (x − q·P)_{π_i} <
d_i`` for every i is unique (Popov normal form of x modulo the row module of
P).  The quotient is the polynomial part of ``x_π·P_π⁻¹`` (``P_π`` = the pivot
columns of P):

    q_j = (x_π · adj P_π)_j  quo  det P_π.

Proof: ``P_π`` is column reduced with column degrees d and leading column
matrix I (Popov), so ``(x_π − q·P_π) = S·P_π`` with ``S = x_π P_π⁻¹ − q``
strictly proper has column degrees < d.  (Neiger & Vu, "Computing canonical
bases of modules of univariate relations", ISSAC 2017, §2; the same quotient as
SageMath's ``Matrix_polynomial_dense.reduce``.)

Cost: adj and det of the k×k ``P_π`` once (k ≤ 2: closed form, 3 products;
else by evaluation and interpolation, O(k³·deg) rational operations in C — 0.7 ms
of overhead for a 2×2 of degree 10), then per row k² + k·m polynomial
products and k divisions — instead of one pass over the whole row per removed
leading term (``_dense.reduce_rows``), which was quadratic in the degree.
"""

from __future__ import annotations

from dataclasses import dataclass

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev

__all__ = ["reduce_modulo_popov", "adjugate", "PopovDivisor"]


#: Up to this size the adjugate is taken by cofactors (minors of size ≤ 3 by their
#: closed forms, :func:`~uio_ring.ring._dense.det_closed_form`); above, by evaluation.
COFACTOR_MAX_SIZE = 4


def adjugate(p: dn.Rows, k: int) -> tuple[flint.fmpq_poly, dn.Rows]:
    """``(det P, adj P)`` of a k×k nonsingular P: by cofactors up to
    :data:`COFACTOR_MAX_SIZE`, else by evaluation at points where P(x) is nonsingular
    and interpolation (degree bounds from
    :func:`~uio_ring.ring._evaluation.minor_degree_bound`).
    Precondition: k ≥ 1, P nonsingular (not checked)."""
    if k == 1:
        return p[0][0], [[bk.ONE]]
    if k == 2:  # the closed form: no evaluation points, no interpolation
        (a, b), (c, d) = p
        return a * d - b * c, [[d, -b], [-c, a]]
    if k <= COFACTOR_MAX_SIZE:
        return _adjugate_by_cofactors(p, k)
    return _adjugate_by_evaluation(p, k)


def _adjugate_by_cofactors(p: dn.Rows, k: int) -> tuple[flint.fmpq_poly, dn.Rows]:
    """:func:`adjugate` from the k² cofactors: entry (j, i) of adj P is
    (−1)^(i+j)·det of P without row i and column j, and det P = Σ_j P[0][j]·adj[j][0]."""
    adj = [[bk.ZERO] * k for _ in range(k)]
    for i in range(k):
        rows = p[:i] + p[i + 1 :]
        for j in range(k):
            minor = dn.det_closed_form([r[:j] + r[j + 1 :] for r in rows], k - 1)
            adj[j][i] = -minor if (i + j) % 2 else minor
    det = bk.ZERO
    for j in range(k):
        if not p[0][j].is_zero():
            det += p[0][j] * adj[j][0]
    return det, adj


def _adjugate_by_evaluation(p: dn.Rows, k: int) -> tuple[flint.fmpq_poly, dn.Rows]:
    """:func:`adjugate` by evaluation and interpolation."""
    dbound = ev.minor_degree_bound(p, k, k, k)
    abound = ev.minor_degree_bound(p, k, k, k - 1)
    count = max(dbound, abound) + 1
    coeffs = ev.coefficient_mats(p, k, k)
    xs: list[int] = []
    dets: list[flint.fmpq] = []
    adjs: list[list[flint.fmpq]] = []
    for x in ev.points():
        if len(xs) == count:
            break
        px = ev.evaluate(coeffs, x)
        dx = px.det()
        if dx == 0:
            continue
        xs.append(x)
        dets.append(dx)
        adjs.append([dx * e for e in px.inv().entries()])
    det = ev.interpolate(xs[: dbound + 1], dets[: dbound + 1])
    polys = ev.interpolate_columns(
        flint.fmpq_mat(abound + 1, k * k, [e for row in adjs[: abound + 1] for e in row]), xs[: abound + 1]
    )
    return det, [polys[i * k : (i + 1) * k] for i in range(k)]


@dataclass(frozen=True)
class PopovDivisor:
    """Division with remainder by a fixed Popov basis, row by row.

    ``det`` and ``adj`` of the pivot columns ``P_π`` are computed once
    (:func:`adjugate`); each :meth:`remainder` then costs k² + k·m polynomial
    products and k divisions, on the quotient's degree (deg x − d), so a row
    that is already nearly reduced is cheap.  Precondition: ``basis`` is in
    row-wise Popov form (zero shift) with no zero row (not checked; only the
    pivot columns must be column reduced with leading matrix I).

    >>> d = bk.from_coeffs([0, 1])
    >>> div = PopovDivisor.of([[d, bk.ONE]])   # pivot δ in column 0
    >>> [bk.to_str(e, "d") for e in div.remainder([d**2 + 1, bk.ZERO])]
    ['1', '-d']
    """

    basis: dn.Rows
    cols: tuple[int, ...]
    degs: tuple[int, ...]
    det: flint.fmpq_poly
    adj: dn.Rows
    #: ``(P, G)`` with ``P·G == basis`` exactly (see :meth:`of`), or None
    via: tuple[dn.Rows, dn.Rows] | None = None
    #: the columns of the nonzero entries of each row the quotients multiply (basis or G)
    support: tuple[tuple[int, ...], ...] = ()

    @staticmethod
    def of(basis: dn.Rows, via: tuple[dn.Rows, dn.Rows] | None = None) -> PopovDivisor:
        """The divisor by ``basis``.  ``via = (P, G)``: another basis G of the same
        module with ``basis == P·G`` exactly (P unimodular; the caller's proof, e.g. P
        the transform of the Popov reduction of G).  Then each quotient q (of
        ``x − q·basis``) is applied as ``x − (q·P)·G``: the same remainder, with
        products by the entries of G instead of those of the basis — a gain when G
        has far smaller coefficients (the integer kernel rows of an elimination
        against their Popov form, whose monic pivots bring rationals of ≈ 150 bits;
        22×20 tall: 4.4 → 3.1 ms for the 20 rows)."""
        lead = [dn.leading_position(row) for row in basis]
        cols = tuple(j for _, j in lead)
        det, adj = adjugate([[row[c] for c in cols] for row in basis], len(basis))
        rows = basis if via is None else via[1]
        support = tuple(tuple(c for c, e in enumerate(row) if not e.is_zero()) for row in rows)
        return PopovDivisor(basis, cols, tuple(d for d, _ in lead), det, adj, via, support)

    def pending(self, row: list[flint.fmpq_poly]) -> bool:
        """True if some entry of ``row`` in a pivot column is not below its pivot degree."""
        return any(row[c].degree() >= d for c, d in zip(self.cols, self.degs, strict=True))

    def remainder(self, row: list[flint.fmpq_poly]) -> list[flint.fmpq_poly]:
        """The remainder of ``row`` modulo the basis (a new list)."""
        new = list(row)
        if not self.pending(row):
            return new
        k = len(self.cols)
        y = [row[c] for c in self.cols]
        qs = []
        for jj in range(k):
            s = bk.ZERO
            for i in range(k):
                if y[i] and self.adj[i][jj]:
                    s = s + y[i] * self.adj[i][jj]
            qs.append(s // self.det)
        rows = self.basis
        if self.via is not None:  # q·basis = (q·P)·G
            p, rows = self.via
            qs = [sum((qs[i] * p[i][jj] for i in range(k) if not p[i][jj].is_zero()), bk.ZERO)
                  for jj in range(len(rows))]
        support = self.support or tuple(tuple(range(len(new))) for _ in rows)
        for q, brow, cols in zip(qs, rows, support, strict=True):
            if not q:
                continue
            for c in cols:
                e = brow[c]
                if e:
                    new[c] = new[c] - q * e
        return new


def reduce_modulo_popov(x: dn.Rows, basis: dn.Rows, via: tuple[dn.Rows, dn.Rows] | None = None) -> dn.Rows:
    """The rows of ``x`` reduced modulo the row module of ``basis`` (new rows).

    Afterwards every entry in the pivot column of a basis row has lower degree
    than that pivot, and each output row differs from its input row by a
    polynomial combination of the basis rows.  Precondition: ``basis`` is in
    row-wise Popov form (zero shift) with no zero row, and its rows have the
    length of the rows of ``x`` (not checked).  ``via``: see :meth:`PopovDivisor.of`.
    """
    if not x or not basis:
        return dn.copy(x)
    lead = [dn.leading_position(row) for row in basis]
    if not any(row[j].degree() >= d for row in x for d, j in lead):
        return dn.copy(x)
    div = PopovDivisor.of(basis, via)
    return [div.remainder(row) for row in x]
