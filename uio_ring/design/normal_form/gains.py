"""The observer gains of Niederwieser et al. (2022): one Levant robust exact differentiator per chain.

Chain ``j`` (length ``μ_j``) gets gains ``κ_{j,μ_j−1}, …, κ_{j,0}`` (top row to bottom
row).  The necessary condition (18) asks ``κ_{j,0} > Σ_i L_i |b̄_{e_j,i}|`` wherever
the bound is nonzero, with ``b̄_{e_j,·}`` the row of ``B̄ = T⁻¹ B`` at the chain's last
state (the paper's ``d̄_{e_j,·}``) and ``L_i`` the bounds of the model's unknown input.
By default ``L_j = max(safety · Σ_i L_i |b̄_{e_j,i}|, lipschitz_floor)`` and Levant's
standard parameters (Remark 3.3); ``safety = 8`` and ``lipschitz_floor = 10``
reproduce the paper's gains (89).

>>> g = observer_gains((2,), ((Fraction(1),),), (Fraction(1, 2),))
>>> g.lipschitz, [float(k) for k in g.kappa[0]]
((Fraction(10, 1),), [4.74341649025, 11.0])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.design.red_gains import levant_gains
from uio_ring.errors import DimensionError, DomainError
from uio_ring.ring.poly import exact_fraction
from uio_ring.ring.qmatrix import QMatrix

__all__ = ["ObserverGains", "input_bounds", "model_input_bounds", "observer_gains"]


@dataclass(frozen=True)
class ObserverGains:
    """The RED gains per chain.

    Attributes
    ----------
    lipschitz
        The RED constant ``L_j`` per chain (0 for explicit gains).
    kappa
        ``kappa[j] = (κ_{j,μ_j−1}, …, κ_{j,0})``.
    need
        ``Σ_i L_i |b̄_{e_j,i}|`` per chain: (18) asks ``κ_{j,0} >`` it where it is nonzero.
    """

    lipschitz: tuple[Fraction, ...]
    kappa: tuple[tuple[Fraction, ...], ...]
    need: tuple[Fraction, ...]


def input_bounds(bounds: Any, m: int, what: str) -> tuple[Fraction, ...]:
    """``L_i`` (one per unknown input, or one number for all), exact and ``≥ 0``."""
    if bounds is None:
        if m:
            raise DimensionError(f"input_bounds: {m} bound(s) needed ({what}), got None")
        return ()
    if isinstance(bounds, (int, float, str, Fraction)):
        bounds = [bounds] * m
    out = tuple(exact_fraction(x, f"input_bounds[{i}]") for i, x in enumerate(bounds))
    if len(out) != m:
        raise DimensionError(f"input_bounds has {len(out)} entries; expected {m} ({what})")
    for i, x in enumerate(out):
        if x < 0:
            raise DomainError(f"input_bounds[{i}] = {x} must be ≥ 0")
    return out


def model_input_bounds(w_transform: QMatrix, bounds: tuple[Fraction, ...]) -> tuple[Fraction, ...]:
    """Bounds of the model's unknown input ``w_m = w_transform · w``: ``Σ_j |w_transform[i, j]| L_j``."""
    return tuple(sum((abs(c) * L for c, L in zip(row, bounds, strict=True)), Fraction(0)) for row in w_transform.tolist())


def observer_gains(
    mu: tuple[int, ...],
    b_bar_rows: tuple[tuple[Fraction, ...], ...],
    bounds: tuple[Fraction, ...],
    *,
    gains: Sequence[Sequence[Any]] | None = None,
    lipschitz: Sequence[Any] | None = None,
    safety: Any = 8,
    lipschitz_floor: Any = 10,
    lambdas: Sequence[Any] | None = None,
) -> ObserverGains:
    """Gains per chain (explicit ``gains``, or Levant's with ``lipschitz`` or the default rule),
    checked against (18).

    Raises
    ------
    DimensionError
        Wrong number of chains or gains.
    DomainError
        Gains that violate (18).
    """
    p = len(mu)
    need = tuple(sum((abs(d) * L for d, L in zip(row, bounds, strict=True)), Fraction(0)) for row in b_bar_rows)
    if gains is not None:
        if len(gains) != p:
            raise DimensionError(f"gains has {len(gains)} chains; the normal form has {p} (mu = {mu})")
        kappa = []
        for j, g in enumerate(gains):
            gj = tuple(exact_fraction(x, f"gains[{j}][{i}]") for i, x in enumerate(g))
            if len(gj) != mu[j]:
                raise DimensionError(f"gains[{j}] has {len(gj)} entries; chain {j + 1} has length {mu[j]}")
            kappa.append(gj)
        lips = tuple(Fraction(0) for _ in range(p))
    else:
        if lipschitz is not None:
            if len(lipschitz) != p:
                raise DimensionError(f"lipschitz has {len(lipschitz)} entries; expected {p} (one per chain)")
            lips = tuple(exact_fraction(x, f"lipschitz[{j}]") for j, x in enumerate(lipschitz))
        else:
            sf, fl = exact_fraction(safety, "safety"), exact_fraction(lipschitz_floor, "lipschitz_floor")
            lips = tuple(max(sf * nd, fl) for nd in need)
        kappa = [levant_gains(mu[j], lips[j], lambdas=lambdas) for j in range(p)]
    for j in range(p):
        if need[j] and not kappa[j][-1] > need[j]:
            raise DomainError(
                f"gains of chain {j + 1} violate the necessary condition (18): κ_{{{j + 1},0}} = {kappa[j][-1]} "
                f"≤ Σ_i L_i |b̄_{{e_{j + 1},i}}| = {need[j]} (≈ {float(need[j]):.6g})"
            )
    return ObserverGains(lips, tuple(kappa), need)
