"""The left kernel of an (n+1)×n matrix of rank n, and the reduced solution of
``X·M = W``, from its maximal minors: one kernel row, no Toeplitz system.

Kernel.  With c_i = (−1)^i·det M_î (M without row i), ``c·M = 0``: entry l of c·M is the
Laplace expansion along the last column of ``[M | M·e_l]``, which has two equal columns.
The kernel has rank 1 and c ≠ 0 spans it over Q(δ), so ``c / gcd(c)`` spans it over
Q[δ] (a kernel vector is a rational multiple of c, a polynomial one a polynomial multiple
of the primitive c / gcd(c)), and made monic at its leading position it is the Popov
basis (a single row: no other row to reduce).

Solution (M left unimodular: the minors coprime, gcd(c) = 1).  Let π be the pivot of K,
R the other n rows, f = det M_R = ±c_π and A = adj M_R (``A·M_R = f·I``).  A row x with
``x·M = w`` splits into x_π and x_R, and ``x_R = (w − x_π·m_π)·A / f`` is a polynomial
iff ``x_π·v ≡ w·A (mod f)`` with ``v = m_π·A`` (its entries are ±c_r, r ∈ R: Cramer).
Reduced modulo K means ``deg x_π < deg f``.  Since gcd(f, v) = 1, a combination
``w_λ = Σ_j λ_j·v_j`` is coprime to f for all λ outside finitely many hyperplanes (a
root of f kills one combination each); with one, ``x_π = (Σ_j λ_j (w·A)_j)·w_λ⁻¹ mod f``
is the only candidate, and the exact division for x_R decides whether it solves all n
congruences (a remainder: no solution).  The adjugate is checked exactly
(``A·M_R = f·I``); with the exact divisions that proves ``X·M = W``.

Cost: n + 1 determinants of size n and their gcd for K; for X an adjugate (n² minors of
size n − 1), one extended gcd of degree deg f (flint) and O(n²) products — instead of
the block-Toeplitz systems of :mod:`uio_ring.ring._kernel_basis` with (n + 1)·(deg f + 1)
unknowns.  Random (n+1)×n with coefficients in [−3, 3] (Hermite's U / the left kernel):
3×2 of degree 16, 4.6 / 3.2 → 1.3 / 0.13 ms; 4×3 of degree 48, 413 / 235 → 71 / 0.5 ms;
5×4 of degree 48, 2.5 s / 0.87 s → 0.20 s / 1.1 ms.
"""

from __future__ import annotations

from dataclasses import dataclass

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._division import adjugate
from uio_ring.ring._predicates import det_raw

__all__ = ["MINORS_MAX_COLUMNS", "MinorsKernel", "kernel_by_minors", "solution_by_minors"]

#: At most this many columns: the determinants are by formula (n ≤ 4) and the adjugate is
#: n² of them; beyond, the Toeplitz systems while their size allows
#: (:data:`~uio_ring.ring._kernel_basis.MAX_UNKNOWNS`), these minors otherwise.
MINORS_MAX_COLUMNS = 4

#: The combinations λ tried for w_λ: a unit vector each, then these weights (j + 1)^t.
_POWERS = (1, 2, 3)


@dataclass(frozen=True)
class MinorsKernel:
    """The Popov row of the kernel and whether M's maximal minors are coprime."""

    #: The Popov basis: one row, monic at its leading position.
    row: list[flint.fmpq_poly]
    #: gcd of the maximal minors is 1 (M is left unimodular, H = [I; 0]).
    coprime: bool


def kernel_by_minors(a: dn.Rows, n: int) -> MinorsKernel | None:
    """The kernel of the (n+1)×n rows ``a`` from its maximal minors, or None when their
    rank is < n (every minor zero).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1, 0], [0, 1], [d, d**2]]")     # kernel [d, d², −1]
    >>> got = kernel_by_minors(M._r, 2)
    >>> PolyMatrix._new([got.row], 1, 3, "d"), got.coprime
    (PolyMatrix([[d, d**2, -1]]), True)
    """
    c = [det_raw(a[:i] + a[i + 1 :], n) for i in range(n + 1)]
    c = [-x if i % 2 else x for i, x in enumerate(c)]
    g = bk.ZERO
    for x in c:
        g = x if g.is_zero() else g.gcd(x)
    if g.is_zero():
        return None
    row = [x / g for x in c] if g.degree() > 0 else c
    _, j = dn.leading_position(row)
    lc = bk.lc(row[j])
    return MinorsKernel([x / lc for x in row], g.degree() == 0)


def solution_by_minors(a: dn.Rows, n: int, kernel: MinorsKernel, rhs: dn.Rows) -> dn.Rows | None:
    """The X with ``X·M = rhs`` reduced modulo the kernel row (module text), or None when
    there is none or no combination w_λ coprime to f was found among those tried.
    Precondition: ``kernel = kernel_by_minors(a, n)`` with ``kernel.coprime``.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1, 0], [0, 1], [d, d**2]]")
    >>> X = solution_by_minors(M._r, 2, kernel_by_minors(M._r, 2), dn.identity(2))
    >>> PolyMatrix._new(X, 2, 3, "d")
    PolyMatrix([[1, 0, 0], [0, 1, 0]])
    """
    _, pi = dn.leading_position(kernel.row)
    rest = [r for r in range(n + 1) if r != pi]
    m_r = [a[r] for r in rest]
    f, adj = adjugate(m_r, n)
    # A·M_R = f·I certifies the adjugate; with it and the exact divisions below, X·M = W
    # holds by the algebra of the module text.  (Checking X·M itself, X of large entries,
    # took half of the time: a 9×8 of degree 32, X of degree 255 with 39-kbit
    # coefficients: 5.6 of 11.5 s; this check, 0.01 s.)
    if dn.matmul(adj, m_r, n, n, n) != [[f if i == j else bk.ZERO for j in range(n)] for i in range(n)]:
        raise ArithmeticError("the adjugate failed its check A·M_R = det·I")  # pragma: no cover - proven
    v = dn.matmul([a[pi]], adj, 1, n, n)[0]
    # f constant: x_π = 0 (degree < 0), every row of X is w·A / f
    found = ([0] * n, bk.ZERO) if f.degree() == 0 else _coprime_combination(v, f, n)
    if found is None:
        return None
    lam, s = found
    out: dn.Rows = []
    for y in rhs:
        b = dn.matmul([y], adj, 1, n, n)[0]
        z = bk.ZERO
        for lj, bj in zip(lam, b, strict=True):
            if lj:
                z += bj * lj
        x_pi = (z * s) % f
        x = [bk.ZERO] * (n + 1)
        x[pi] = x_pi
        for j, r in enumerate(rest):
            q, rem = divmod(b[j] - x_pi * v[j], f)
            if not rem.is_zero():
                return None  # x_π fails congruence j: no solution
            x[r] = q
        out.append(x)
    return out


def _coprime_combination(
    v: list[flint.fmpq_poly], f: flint.fmpq_poly, n: int
) -> tuple[list[int], flint.fmpq_poly] | None:
    """``(λ, s)`` with ``w_λ = Σ λ_j v_j`` coprime to f and ``s·w_λ ≡ 1 (mod f)``, or None."""
    tries = [[int(i == j) for i in range(n)] for j in range(n)]
    tries += [[(j + 1) ** t for j in range(n)] for t in _POWERS if n > 1]
    for lam in tries:
        w = bk.ZERO
        for lj, vj in zip(lam, v, strict=True):
            if lj:
                w += vj * lj
        if w.is_zero():
            continue
        g, s, _ = w.xgcd(f)
        if g.degree() == 0:
            return lam, s / g
    return None
