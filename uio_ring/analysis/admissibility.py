"""Admissibility of a set (A, C, W_1, …, W_v) (Grip & Saberi 2010, Definition 2).

For ``x' = A x + φ(t, x)``, ``y = C x`` with Jacobian ``∂φ/∂x = Σ_k ζ_k(t, x) W_k``,
the set is *admissible* when every unobservability subspace

    𝒮_i = ker [C; C A; …; C A^{i−1}],   i = 1, …, n,

is invariant under every ``W_k``: ``W_k 𝒮_i ⊂ 𝒮_i``.  Admissible sets, and only
those, have a high-gain observer in the canonical form of the paper (its
Theorem 2; see :func:`uio_ring.analysis.canonical_form.canonical_form`).

The test is exact: ``O_i W_k N_i = 0`` with ``N_i`` a kernel basis of ``O_i``.
The loop stops when 𝒮_i stops shrinking (it is then constant).

>>> A = [[0, 1], [0, 0]]; C = [[1, 0]]
>>> admissibility(A, C, [[[0, 0], [1, 0]]]).holds        # x2' = x1: down, fine
True
>>> print(admissibility(A, C, [[[0, 1], [0, 0]]]).reason)  # x1' gets x2: up, not admissible
W[0] maps v = (0, 1) in 𝒮_1 to W[0]·v = (1, 0), which is not in 𝒮_1 = ker [C]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.analysis import _subspaces as sp
from uio_ring.analysis.report import Report

__all__ = ["AdmissibilityReport", "admissibility"]


def _fmt(v: tuple[Fraction, ...]) -> str:
    return "(" + ", ".join(str(x) for x in v) + ")"


@dataclass(frozen=True)
class AdmissibilityReport(Report):
    """Verdict of :func:`admissibility`.

    Attributes
    ----------
    holds
        ``W_k 𝒮_i ⊂ 𝒮_i`` for every i and k.
    reason
        Empty when it holds; otherwise which ``W_k`` maps which vector out of which 𝒮_i.
    index
        The first ``i`` (1-based, as 𝒮_i) at which invariance fails, or ``None``.
    matrix
        The position ``k`` (0-based) of the first failing ``W_k`` in the given list, or ``None``.
    vector, image
        A basis vector ``v`` of 𝒮_i and ``W_k v ∉ 𝒮_i`` (tuples of Fractions), or ``None``.
    dimensions
        ``dim 𝒮_1, dim 𝒮_2, …`` up to the first i where it stops shrinking (or fails).
    """

    holds: bool
    reason: str
    index: int | None = None
    matrix: int | None = None
    vector: tuple[Fraction, ...] | None = None
    image: tuple[Fraction, ...] | None = None
    dimensions: tuple[int, ...] = ()

    @property
    def name(self) -> str:
        return "admissibility of (A, C, W) (Grip & Saberi 2010)"

    def to_dict(self) -> dict[str, Any]:
        return {
            "holds": self.holds,
            "reason": self.reason,
            "index": self.index,
            "matrix": self.matrix,
            "vector": None if self.vector is None else [str(x) for x in self.vector],
            "image": None if self.image is None else [str(x) for x in self.image],
            "dimensions": list(self.dimensions),
        }


def admissibility(A: Any, C: Any, W: Sequence[Any]) -> AdmissibilityReport:
    """Is ``(A, C, W_1, …, W_v)`` admissible?  A report; never raises for "no".

    Parameters
    ----------
    A, C
        n×n and p×n constant rational matrices (``PolyMatrix`` of degree ≤ 0,
        nested lists, or text).
    W
        The matrices ``W_k`` (each n×n) of the Jacobian decomposition
        ``∂φ/∂x = Σ ζ_k W_k``; an empty list is always admissible.

    Returns
    -------
    AdmissibilityReport
        ``holds``, ``reason`` and, when it fails, the first ``i``, the first
        failing ``W_k`` and a vector of 𝒮_i that it maps out of 𝒮_i.

    Raises
    ------
    DimensionError
        Shapes that do not fit (the message names the matrix).

    Algorithm
    ---------
    Grip & Saberi (2010), Definition 2, eq. (15): for i = 1, 2, …: ``N_i`` = kernel
    basis of ``O_i = [C; …; C A^{i−1}]``; fails at the first column ``v`` of ``N_i``
    and ``k`` with ``O_i W_k v ≠ 0``.  Stops when ``dim 𝒮_i = dim 𝒮_{i−1}`` (then
    𝒮_j = 𝒮_i for all j ≥ i).  At most n + 1 kernels of matrices with ≤ n p rows.

    Examples
    --------
    Example 1 of the paper (already in the form (8)–(9); ``W_1`` couples upwards):

    >>> A = [[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]
    >>> C = [[1,0,0,0,0],[0,0,1,0,0]]
    >>> W1 = [[0,-1,0,1,0],[0,0,0,0,1],[0,-1,0,1,0],[1,0,0,0,1],[0,1,0,0,0]]
    >>> r = admissibility(A, C, [W1])
    >>> r.holds, r.index, r.matrix, [str(x) for x in r.vector], [str(x) for x in r.image]
    (False, 1, 0, ['0', '1', '0', '0', '0'], ['-1', '0', '-1', '0', '1'])
    """
    Aq, Cq, Ws = sp.read_triple(A, C, W)
    n = Aq.nrows()
    dims: list[int] = []
    previous = n
    # invariant: every 𝒮_j with j < i is W_k-invariant for all k
    for i in range(1, n + 1):
        O = sp.observability_stack(Aq, Cq, i)
        N = sp.kernel(O)
        dims.append(N.ncols())
        for k, Wk in enumerate(Ws):
            R = O * Wk * N
            bad = next((j for j in range(N.ncols()) if any(R[r, j] != 0 for r in range(R.nrows()))), None)
            if bad is None:
                continue
            v = sp.column(N, bad)
            image = sp.as_tuple(Wk * v)
            vec = sp.as_tuple(v)
            stack = "[C]" if i == 1 else ("[C; C A]" if i == 2 else f"[C; C A; …; C A^{i - 1}]")
            reason = (f"W[{k}] maps v = {_fmt(vec)} in 𝒮_{i} to W[{k}]·v = {_fmt(image)}, "
                      f"which is not in 𝒮_{i} = ker {stack}")
            return AdmissibilityReport(False, reason, i, k, vec, image, tuple(dims))
        if N.ncols() in (previous, 0):  # 𝒮_i = 𝒮_{i−1} is A-invariant: constant from here
            break
        previous = N.ncols()
    return AdmissibilityReport(True, "", dimensions=tuple(dims))
