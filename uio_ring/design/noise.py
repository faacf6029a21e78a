"""Choosing a design for noise: default observer rates, and the least-noise search.

The figures come from the float model (:func:`uio_ring.numeric.performance.performance`);
the choice they lead to is then built exactly and certified like any other design.
The search is finite and deterministic (documented below), so the same system gives
the same design.

>>> from uio_ring import DelaySystem
>>> default_rate(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
Fraction(5, 1)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from uio_ring.errors import DomainError, SimulationError
from uio_ring.ring.poly import exact_fraction
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["default_rate", "pole_patterns", "least_noise", "NOISE_CHOICES", "SPREADS"]

#: The words ``poles`` accepts besides a list of rationals.
NOISE_CHOICES = ("min-noise",)
#: Ratios of a geometric pole pattern ``−α·(1, q, q², …)`` tried by the least-noise search.
SPREADS = (Fraction(1), Fraction(11, 10), Fraction(5, 4), Fraction(3, 2), Fraction(2))
#: Decay rates tried, as multiples of the requested rate α (faster poles amplify noise more:
#: measured on the examples, the slowest allowed rate always won).
SPEEDS = (Fraction(1),)


def default_rate(sys: DelaySystem) -> Fraction:
    """The observer rate used when none is given: ``⌈‖A(1)‖∞⌉`` (at least 1).

    ``‖A(1)‖∞`` (largest absolute row sum of ``A(δ)`` at ``δ = 1``, exact) bounds the
    modulus of every eigenvalue of ``A(1)``, the plant seen by slow signals; an observer
    whose error decays at least that fast is not slower than the plant it watches.  The
    rounding keeps the poles small integers.
    """
    A1 = sys.A.eval(1).coefficient_lists()
    rows = A1[0] if A1 else []
    norm = max((sum(abs(v) for v in row) for row in rows), default=Fraction(0))
    return Fraction(max(1, math.ceil(norm)))


def pole_patterns(l_star: int, rate: Fraction) -> list[tuple[Fraction, ...]]:
    """The pole sets tried: ``−s·α·(1, q, …, q^{l*−1})`` for ``s`` in :data:`SPEEDS` and
    ``q`` in :data:`SPREADS` — every pole at least as fast as ``−α``; repeated poles
    (``q = 1``) first.

    >>> pole_patterns(2, Fraction(10))[:2]
    [(Fraction(-10, 1), Fraction(-10, 1)), (Fraction(-10, 1), Fraction(-11, 1))]
    """
    out: list[tuple[Fraction, ...]] = []
    for s in SPEEDS:
        for q in SPREADS:
            pat = tuple(-s * rate * q**i for i in range(l_star))
            if pat not in out:
                out.append(pat)
    return out


def _objective(design: Any, h: Any) -> float:
    from uio_ring.numeric.performance import performance

    return float(performance(design.numeric(h=h), rtol=1e-2).noise_gain.max())


def least_noise(sys: DelaySystem, ranked: Sequence[Any], choice: str, *, rate: Any, assemble: Callable[..., Any],
                report: Any = None, candidates: int = 3) -> Any:
    """The design of least peak-to-peak noise gain (``max_i Σ_j P_ij``: the largest error
    for output noise bounded by 1) among, for each ``l*`` the search found, the first
    ``candidates`` assemblies of the design search (least lag first), and every pole
    pattern of :func:`pole_patterns`.

    ``rate`` (α) is the slowest decay allowed (default :func:`default_rate`).  Needs the
    system's ``h`` when it has delays (the gain depends on it).  Ties keep the earlier
    candidate (smaller lag) and the earlier pattern.
    """
    if choice not in NOISE_CHOICES:
        raise DomainError(f"poles = {choice!r}: expected a list of rationals or one of {NOISE_CHOICES}")
    alpha = default_rate(sys) if rate is None else exact_fraction(rate, "rate")
    if alpha <= 0:
        raise DomainError(f"rate = {alpha} must be > 0 (the slowest decay rate allowed)")
    if not sys.is_delay_free and sys.h is None:
        raise SimulationError("poles='min-noise' needs the system's h (the noise gain depends on the delay)")
    best: tuple[float, Any] | None = None
    per_l: dict[int, list[Any]] = {}
    for asm in ranked:
        per_l.setdefault(asm.index.l_star, [])
        if len(per_l[asm.index.l_star]) < candidates:
            per_l[asm.index.l_star].append(asm)
    for asm in [a for group in per_l.values() for a in group]:
        for pat in pole_patterns(asm.index.l_star, alpha):
            design = assemble(sys, asm.steps12, asm.Lam, index=asm.index, F_stack=asm.F_stack,
                              O_left_inverse=asm.O_left_inverse, T_left_inverse=asm.T_left_inverse, poles=pat,
                              choice=f"{asm.choice}; poles of least noise gain at rate ≥ {alpha}",
                              assumptions=report)
            gain = _objective(design, sys.h)
            if best is None or gain < best[0] * (1 - 1e-9):
                best = (gain, design)
    assert best is not None  # ranked is not empty and every l* has patterns
    return best[1]
