"""One elimination step of algorithm (4)–(5): the w-free rows of ``[[Δ_k A, Δ_k B], [G_k, F_k]]``.

``P_k·[[Δ_k B, Δ_k A], [F_k, G_k]] = [[F_{k+1}, G_{k+1}], [0, Δ_{k+1}]]`` with ``P_k``
unimodular and ``F_{k+1}`` the Hermite form of ``S_k = [Δ_k B; F_k]``
(:mod:`uio_ring.analysis.observability`).  Two ways, both exact:

* ``F_k = I`` (the usual case once ``[C B; D]``-like blocks have full column rank
  with coprime maximal minors): ``S_k = [Δ_k B; I]`` and
  ``P_k = [[0, I], [I, −Δ_k B]]`` (determinant ±1) give ``F_{k+1} = I``,
  ``G_{k+1} = G_k`` and ``Δ_{k+1} = Δ_k A − Δ_k B·G_k`` — no Hermite form and no
  product with a transform.  When ``G_k = X·R`` came from a Hermite step
  ``[X; K]·S = [I; 0]`` (so ``X·S = I``, ``K·S = 0``, and ``K·R`` were that step's
  w-free rows), ``Δ_k B·X`` is first reduced modulo L(K), given by a weak Popov
  basis (its Popov normal form, :func:`~uio_ring.ring.row_basis.remainder_rows`):
  ``Δ_{k+1} = Δ_k A − u·R`` with ``u = Δ_k B·X − t·K``.  This changes ``Δ_{k+1}`` by ``t·(K·R)``, a combination of
  rows already in the row module of ``N_k`` — which, by the argument in
  :mod:`uio_ring.analysis.observability`, changes neither the later row modules nor
  their invariant factors.  It is what keeps the coefficients small: X is a
  Bézout-sized left inverse (random 16-state spec of δ-degree 16: ``C B`` 5×4 of
  degree 32, X of degree 127 with 9.5 kbit coefficients), and ``Δ_k B·X`` carried
  its size into every new row (≈ 4.8 kbit and 160 degrees more per step, which the
  row reduction of :mod:`uio_ring.ring.row_basis` only partly removed), whereas the
  minimal solution ``u`` of ``u·S = Δ_k B`` does not (≈ 0.35 kbit and 16 degrees
  per step).
* otherwise the Hermite form with its transform: when ``F_k`` is empty (the first
  block, e.g. ``S_1 = C B``), the block-Toeplitz path of
  :func:`uio_ring.ring.hermite.hermite` whatever the row count (one exact
  nullspace and one square solve, U reduced modulo the Popov kernel basis:
  2 s instead of 38 s of Euclidean elimination with growing ``xgcd`` cofactors on
  the 5×4 ``C B`` of degree 32 of a random 16-state spec of δ-degree 16, and U of
  degree 128 instead of 159); elimination when that path declines.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> st = eliminate_w(PolyMatrix("[[d]]"), PolyMatrix("[[1, 0]]"), PolyMatrix("[[1]]"), PolyMatrix("[[0, 1]]"))
>>> st.F, st.G, st.free
(PolyMatrix([[1]]), PolyMatrix([[0, 1]]), PolyMatrix([[1, -d]]))
"""

from __future__ import annotations

from dataclasses import dataclass

from uio_ring.ring import _dense as dn
from uio_ring.ring.hermite import _hermite_of_dependent_rows, hermite
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.row_basis import is_weak_popov, remainder_rows

__all__ = ["WStep", "eliminate_w"]


@dataclass(frozen=True)
class WStep:
    """``F``, ``G``: the rows ``[G_{k+1}, F_{k+1}]`` (``F`` in Hermite form, full row rank);
    ``free``: the w-free x-parts (raw ``Δ_{k+1}``, before any reduction).

    ``X``, ``R``, ``K`` (None unless a Hermite step made them): ``G = X·R``, and the rows
    ``K·R`` lie in the row module spanned by ``free`` of the step that made them
    (K a weak Popov basis of the left kernel of that step's ``S``)."""

    F: PolyMatrix
    G: PolyMatrix
    free: PolyMatrix
    X: PolyMatrix | None = None
    R: PolyMatrix | None = None
    K: PolyMatrix | None = None


def _is_identity(F: PolyMatrix) -> bool:
    return F.rows == F.cols and F == PolyMatrix.identity(F.rows)


def _weak_popov_rows(K: PolyMatrix) -> PolyMatrix:
    """A weak Popov basis of L(K) (K itself when it already is one)."""
    if not K.rows or is_weak_popov(K):
        return K
    a = [list(r) for r in K._r]
    kept = dn.weak_popov(a)
    return PolyMatrix._new(a[: len(kept)], len(kept), K.cols, K.var)


def eliminate_w(DB: PolyMatrix, DA: PolyMatrix, F: PolyMatrix, G: PolyMatrix,
                prev: WStep | None = None) -> WStep:
    """One step ``P_k`` of algorithm (4)–(5) (module docstring).

    Parameters
    ----------
    DB, DA
        ``Δ_k B`` (s×m) and ``Δ_k A`` (s×n).
    F, G
        ``F_k`` (ρ×m, Hermite form) and ``G_k`` (ρ×n).
    prev
        The step that returned ``F``, ``G`` (optional): its factors ``G = X·R`` let the
        ``F = I`` case use a small solution u (module docstring).

    Returns
    -------
    WStep
        ``F_{k+1}``, ``G_{k+1}`` and the raw ``Δ_{k+1}``; the rows ``[G, F]`` and
        ``[free, 0]`` span the same module as ``[DA, DB]`` and ``[G_k, F_k]`` — with
        ``prev``, up to rows ``t·(K·R)`` of the earlier w-free rows (module docstring).
    """
    if F.rows and _is_identity(F):
        if prev is not None and prev.G is G and prev.X is not None and prev.R is not None \
                and prev.K is not None:
            u = remainder_rows(DB @ prev.X, prev.K) if prev.K.rows else DB @ prev.X
            return WStep(F, G, DA - u @ prev.R, prev.X, prev.R, prev.K)
        return WStep(F, G, DA - DB @ G)
    S = PolyMatrix.vstack(DB, F)
    R = PolyMatrix.vstack(DA, G)
    herm = _hermite_of_dependent_rows(S, min_rows=0) if S.rows and not F.rows else None
    if herm is None:
        herm = hermite(S)
    rho = herm.rank
    PR = herm.U @ R
    U = herm.U
    return WStep(herm.H[0:rho, 0 : S.cols], PR[0:rho, :], PR[rho : PR.rows, :],
                 U[0:rho, :], R, _weak_popov_rows(U[rho : U.rows, :]))
