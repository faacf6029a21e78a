"""The one place where exact coefficients become float64.

The ring never sees a float: :func:`coefficient_arrays` reads the exact
coefficients of a polynomial matrix (``M.coefficient_lists()``, nested lists of
:class:`fractions.Fraction`) and returns them as one float64 array.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.errors import SimulationError

__all__ = ["coefficient_arrays", "poly_matmul", "eval_at_one", "exact_to_float"]


def coefficient_arrays(M: Any, *, name: str = "matrix") -> np.ndarray:
    """Coefficients of ``M = Σ_i M_i δ^i`` as a float64 array of shape ``(deg + 1, rows, cols)``.

    ``M`` is a :class:`~uio_ring.ring.matrix.PolyMatrix` (or anything with
    ``coefficient_lists()`` and ``shape``).  The zero matrix (degree −1) gives
    shape ``(0, rows, cols)``.  A plain array (2-D constant or 3-D stack of
    coefficients) is accepted for convenience.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> coefficient_arrays(PolyMatrix([["d", "1/2"]]))
    array([[[0. , 0.5]],
    <BLANKLINE>
           [[1. , 0. ]]])
    >>> coefficient_arrays(PolyMatrix.zeros(2, 3)).shape
    (0, 2, 3)
    """
    if hasattr(M, "coefficient_lists"):
        hit = _CACHE.get(id(M))
        if hit is not None and hit[0] is M:
            return hit[1].copy()
        arr = _from_lists(M)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[id(M)] = (M, arr)  # holding M keeps id(M) from being reused
        return arr.copy()
    try:
        arr = np.asarray(M, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SimulationError(f"{name}: cannot read {type(M).__name__} as a polynomial matrix") from exc
    if arr.ndim == 2:
        arr = arr[None]
    if arr.ndim != 3:
        raise SimulationError(f"{name}: expected a polynomial matrix, got an array of shape {arr.shape}")
    return _trim(arr, name)


# PolyMatrix is immutable: its float image is computed once (callers get a copy)
_CACHE: dict[int, tuple[Any, np.ndarray]] = {}
_CACHE_SIZE = 256


def _from_lists(M: Any) -> np.ndarray:
    rows, cols = M.shape
    lists = M.coefficient_lists()
    try:  # numpy calls float() on each Fraction: correctly rounded, as exact_to_float
        arr = np.array(lists, dtype=object).reshape(len(lists), rows, cols).astype(float)
    except OverflowError:  # find and name the coefficient beyond float64
        arr = np.zeros((len(lists), rows, cols))
        for k, coeff in enumerate(lists):
            for i, row in enumerate(coeff):
                for j, c in enumerate(row):
                    arr[k, i, j] = exact_to_float(c, f"a coefficient of δ^{k} at ({i}, {j})")
    out = _trim(arr, "matrix")
    out.setflags(write=False)
    return out


def exact_to_float(x: Any, what: str) -> float:
    """``float(x)`` for an exact number, or :class:`SimulationError` when float64 cannot hold it."""
    try:
        return float(x)
    except OverflowError:
        raise SimulationError(
            f"{what} has magnitude about 10^{_log10(x)}, beyond float64 (about 1.8e308): "
            "the exact design is fine but has no float image"
        ) from None


def _log10(c: Any) -> int:
    """Decimal exponent of a Fraction, from bit lengths (its text may exceed Python's 4300 digits)."""
    return round((abs(c.numerator).bit_length() - c.denominator.bit_length()) * 0.30103)


def _trim(arr: np.ndarray, name: str) -> np.ndarray:
    """Drop trailing zero coefficients: ``deg + 1`` rows exactly."""
    nz = [k for k in range(arr.shape[0]) if np.any(arr[k])]
    deg = nz[-1] if nz else -1
    arr = arr[: deg + 1]
    if not np.all(np.isfinite(arr)):
        raise SimulationError(f"{name}: coefficients are not finite")
    return np.ascontiguousarray(arr)


def poly_matmul(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Product of two coefficient stacks: ``(PQ)_k = Σ_{i+j=k} P_i Q_j``.

    >>> P = np.array([[[1.0]], [[2.0]]]); poly_matmul(P, P)[:, 0, 0]
    array([1., 4., 4.])
    """
    if P.shape[0] == 0 or Q.shape[0] == 0:
        return np.zeros((0, P.shape[1], Q.shape[2]))
    out = np.zeros((P.shape[0] + Q.shape[0] - 1, P.shape[1], Q.shape[2]))
    for i in range(P.shape[0]):
        for j in range(Q.shape[0]):
            out[i + j] += P[i] @ Q[j]
    nz = [k for k in range(out.shape[0]) if np.any(out[k])]
    return out[: (nz[-1] + 1 if nz else 0)]


def eval_at_one(P: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """``P(1) = Σ_i P_i``: the action of ``P(δ)`` on a constant signal."""
    return P.sum(axis=0) if P.shape[0] else np.zeros((rows, cols))
