"""One elimination step of algorithm (4)–(5): the w-free rows of ``[[Δ_k A, Δ_k B], [G_k, F_k]]``.

``P_k·[[Δ_k B, Δ_k A], [F_k, G_k]] = [[F_{k+1}, G_{k+1}], [0, Δ_{k+1}]]`` with ``P_k``
unimodular and ``F_{k+1}`` the Hermite form of ``S_k = [Δ_k B; F_k]``
(:mod:`uio_ring.analysis.observability`).  Two ways, both exact:

* ``F_k = I`` (the usual case once ``[C B; D]``-like blocks have full column rank
  with coprime maximal minors): ``S_k = [Δ_k B; I]`` and
  ``P_k = [[0, I], [I, −Δ_k B]]`` (determinant ±1) give ``F_{k+1} = I``,
  ``G_{k+1} = G_k`` and ``Δ_{k+1} = Δ_k A − Δ_k B·G_k`` — one product, no Hermite
  form and no product with a transform.
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

from uio_ring.ring.hermite import _hermite_by_toeplitz, hermite
from uio_ring.ring.matrix import PolyMatrix

__all__ = ["WStep", "eliminate_w"]


@dataclass(frozen=True)
class WStep:
    """``F``, ``G``: the rows ``[G_{k+1}, F_{k+1}]`` (``F`` in Hermite form, full row rank);
    ``free``: the w-free x-parts (raw ``Δ_{k+1}``, before any reduction)."""

    F: PolyMatrix
    G: PolyMatrix
    free: PolyMatrix


def _is_identity(F: PolyMatrix) -> bool:
    return F.rows == F.cols and F == PolyMatrix.identity(F.rows)


def eliminate_w(DB: PolyMatrix, DA: PolyMatrix, F: PolyMatrix, G: PolyMatrix) -> WStep:
    """One step ``P_k`` of algorithm (4)–(5) (module docstring).

    Parameters
    ----------
    DB, DA
        ``Δ_k B`` (s×m) and ``Δ_k A`` (s×n).
    F, G
        ``F_k`` (ρ×m, Hermite form) and ``G_k`` (ρ×n).

    Returns
    -------
    WStep
        ``F_{k+1}``, ``G_{k+1}`` and the raw ``Δ_{k+1}``; the rows ``[G, F]`` and
        ``[free, 0]`` span the same module as ``[DA, DB]`` and ``[G_k, F_k]``.
    """
    if F.rows and _is_identity(F):
        return WStep(F, G, DA - DB @ G)
    S = PolyMatrix.vstack(DB, F)
    R = PolyMatrix.vstack(DA, G)
    herm = _hermite_by_toeplitz(S, min_rows=0) if S.rows and not F.rows else None
    if herm is None:
        herm = hermite(S)
    rho = herm.rank
    PR = herm.U @ R
    return WStep(herm.H[0:rho, 0 : S.cols], PR[0:rho, :], PR[rho : PR.rows, :])
