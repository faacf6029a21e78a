"""Gains of Levant's robust exact differentiator (RED) in the non-recursive form (14) of Niederwieser et al. (2022).

A chain of length μ carries the gains ``κ_{μ−1}, …, κ_1, κ_0`` (top row to bottom
row); ``κ_k`` multiplies ``[σ]^{k/μ}``.  Levant's recursive parameters
``λ_0, λ_1, …`` for a Lipschitz constant ``L`` convert as (Levant 2003; docs/errata.md, N4)::

    k̃_{μ−1} = λ_{μ−1},   k̃_{μ−1−i} = λ_{μ−1−i} · k̃_{μ−i}^{(μ−1−i)/(μ−i)},
    κ_{μ−1−i} = k̃_{μ−1−i} · L^{(i+1)/μ}

so ``κ_0 = λ_0 L`` exactly.  With Levant's standard parameters and
``L = 10`` (μ = 4) and ``L = 112.272`` (μ = 3) this gives the printed gains (89)
of Niederwieser et al. (2022).

The other gains are irrational (fractional powers); they are returned as exact
rationals rounded to 12 significant digits.  ``κ_0`` is exact, so the necessary
condition (18) ``κ_{j,0} > Σ_i L_i |d̄_{e_j,i}|`` is decided exactly.

>>> [float(k) for k in levant_gains(3, 1)]
[2.0, 2.12132034356, 1.1]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from uio_ring.errors import DomainError
from uio_ring.ring.poly import exact_fraction

__all__ = ["LEVANT_LAMBDAS", "levant_gains"]

#: Levant's standard parameters λ_0, λ_1, … (Levant 2003; Levant & Livne 2018 continue 5, 7, 10, 12).
LEVANT_LAMBDAS: tuple[Fraction, ...] = tuple(Fraction(x) for x in ("1.1", "1.5", "2", "3", "5", "7", "10", "12"))


def _round(x: float, digits: int) -> Fraction:
    return Fraction(f"{x:.{digits}g}")


def levant_gains(mu: int, L: Any, *, lambdas: Sequence[Any] | None = None, digits: int = 12) -> tuple[Fraction, ...]:
    """RED gains ``(κ_{μ−1}, …, κ_0)`` of a chain of length ``mu`` for Lipschitz constant ``L``.

    Parameters
    ----------
    mu
        Chain length (differentiator order ``μ − 1``), ``μ ≥ 1``.
    L
        Bound of the disturbance acting on the last row (exact rational, > 0).
    lambdas
        Levant's parameters ``λ_0, …, λ_{μ−1}`` (default :data:`LEVANT_LAMBDAS`).
    digits
        Significant digits of the irrational gains.

    Returns
    -------
    tuple of Fraction
        Top row first; the last entry ``κ_0 = λ_0 L`` is exact.

    Raises
    ------
    DomainError
        ``mu < 1``, ``L ≤ 0``, or too few ``lambdas``.

    Examples
    --------
    The gains of block 1 of (89) in Niederwieser et al. (2022): μ = 4, L = 10.

    >>> [round(float(k), 4) for k in levant_gains(4, 10)]
    [5.3348, 13.1556, 17.2047, 11.0]
    """
    if not isinstance(mu, int) or mu < 1:
        raise DomainError(f"mu = {mu!r}: a chain length is an integer ≥ 1")
    Lf = exact_fraction(L, "L")
    if Lf <= 0:
        raise DomainError(f"L = {Lf} must be positive")
    if Lf > 10**300:  # the gains go through float powers
        raise DomainError("L is beyond 1e300: Levant's gains L^(j/μ) are computed in float64; give smaller input bounds")
    lam = tuple(exact_fraction(x, f"lambdas[{i}]") for i, x in enumerate(LEVANT_LAMBDAS if lambdas is None else lambdas))
    if len(lam) < mu:
        raise DomainError(
            f"{len(lam)} Levant parameters available; a chain of length {mu} needs {mu} (λ_0 … λ_{mu - 1}): "
            "Levant's standard list stops at differentiator order 7, pass lambdas=… (or explicit gains)"
        )
    kt = [0.0] * mu  # k̃_0 … k̃_{μ−1}
    kt[mu - 1] = float(lam[mu - 1])
    for i in range(1, mu):
        k = mu - 1 - i
        kt[k] = float(lam[k]) * kt[k + 1] ** (k / (k + 1))
    out = []
    for k in range(mu - 1, 0, -1):
        out.append(_round(kt[k] * math.pow(float(Lf), (mu - k) / mu), digits))
    out.append(lam[0] * Lf)
    return tuple(out)
