"""The sufficient gain condition (16)/(21) of the hierarchical super-twisting observer, exactly,
and gains that satisfy it (Bejarano, Fridman & Poznyak 2007, Section 2).

Level ``k`` differentiates a signal whose derivative's derivative is
``d/dt M_{k+1}(x − x̃)`` (``x − x̃`` at the last level).  With ``‖x − x̃‖ ≤ ẽ⁺`` (after
the Luenberger transient) and ``‖w‖ ≤ w⁺`` (the paper also needs w bounded only)::

    β_k = ‖M_{k+1}‖ (‖A − K C‖ ẽ⁺ + ‖B − K D‖ w⁺)       (k < l − 1; no ‖M‖ at the last level)
    α_k > β_k,     λ_k > (α_k + β_k) (1 + θ)/(1 − θ) · sqrt(2/(α_k − β_k)),   0 < θ < 1

(the paper prints ``D + K F`` in its letters: a sign error, ``B − K D`` here).  Norms are
bounded exactly from above by Frobenius norms and rational square roots rounded up, so
``β_k`` here is a rational upper bound of the paper's — the condition stays sufficient.
It is very conservative: the paper's own gains for its Example 1 do not satisfy it, and
the observer converges anyway (:class:`STAGainReport` says so, with the margins).

>>> from fractions import Fraction
>>> sqrt_up(Fraction(2)) >= Fraction(14142135, 10000000), sqrt_up(Fraction(4))
(True, Fraction(2, 1))
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.analysis.report import Report
from uio_ring.errors import DomainError, for_option
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction

__all__ = ["LevelMargin", "STAGainReport", "sta_gain_condition", "gains_from_bounds", "sqrt_up", "DEFAULT_THETA"]

#: θ of (16)/(21) when none is given.
DEFAULT_THETA = Fraction(1, 10)
_SCALE = 10**9


def sqrt_up(x: Fraction) -> Fraction:
    """A rational ``≥ √x`` (exact for squares of rationals; else within ``1e-9`` above)."""
    if x < 0:
        raise DomainError(f"sqrt_up: {x} is negative")
    num, den = x.numerator, x.denominator
    rn, rd = math.isqrt(num), math.isqrt(den)
    if rn * rn == num and rd * rd == den:
        return Fraction(rn, rd)
    s = math.isqrt(-(-num * _SCALE**2 // den)) + 1  # ceil(√(x·S²)) or above
    return Fraction(s, _SCALE)


def _frobenius_up(M: PolyMatrix) -> Fraction:
    """A rational upper bound of ``‖M‖₂`` (the Frobenius norm, rounded up)."""
    rows = M.coefficient_lists()[0] if M.rows and M.cols and not M.is_zero() else []
    return sqrt_up(sum((Fraction(v) ** 2 for row in rows for v in row), Fraction(0)))


def lambda_needed(alpha: Fraction, beta: Fraction, theta: Fraction) -> Fraction:
    """A rational upper bound of ``(α + β)(1 + θ)/(1 − θ) · √(2/(α − β))`` (needs α > β)."""
    return (alpha + beta) * (1 + theta) / (1 - theta) * sqrt_up(2 / (alpha - beta))


@dataclass(frozen=True)
class LevelMargin:
    """One level: the bound ``β`` of its perturbation's derivative, its gains and the margins
    ``α/β`` and ``λ/λ_min`` (both must exceed 1; ``λ_min`` the right side of (16)/(21))."""

    level: int
    beta: Fraction
    alpha: Fraction
    lam: Fraction
    holds: bool

    @property
    def alpha_margin(self) -> float:
        return math.inf if self.beta == 0 else float(self.alpha / self.beta)

    def lambda_margin(self, theta: Fraction) -> float:
        if self.alpha <= self.beta:
            return 0.0
        return float(self.lam / lambda_needed(self.alpha, self.beta, theta))


@dataclass(frozen=True)
class STAGainReport(Report):
    """Whether the gains satisfy (16)/(21) for the bounds given, level by level, with margins."""

    levels: tuple[LevelMargin, ...]
    w_bound: Fraction
    e_bound: Fraction
    theta: Fraction
    holds: bool
    reason: str = ""

    @property
    def name(self) -> str:
        return "sufficient gain condition (16)/(21) of the hierarchical super-twisting observer"

    def to_dict(self) -> dict[str, Any]:
        return {"holds": self.holds, "reason": self.reason, "w_bound": str(self.w_bound),
                "e_bound": str(self.e_bound), "theta": str(self.theta),
                "levels": [{"level": lv.level, "beta": str(lv.beta), "alpha": str(lv.alpha), "lambda": str(lv.lam),
                            "alpha_margin": lv.alpha_margin, "lambda_margin": lv.lambda_margin(self.theta),
                            "holds": lv.holds} for lv in self.levels]}

    def _detail_lines(self) -> list[str]:
        out = [f"bounds ‖w‖ ≤ {self.w_bound}, ‖x − x̃‖ ≤ {self.e_bound}, θ = {self.theta}"]
        for lv in self.levels:
            lam = (f"λ/λ_min = {lv.lambda_margin(self.theta):.4g}" if lv.alpha > lv.beta
                   else "no λ suffices while α ≤ β")
            out.append(f"level {lv.level}: β ≤ {float(lv.beta):.4g}, α = {lv.alpha} (α/β = {lv.alpha_margin:.4g}), "
                       f"λ = {lv.lam} ({lam})"
                       + ("" if lv.holds else " — not satisfied"))
        return out


def _betas(design: Any, w_bound: Fraction, e_bound: Fraction) -> list[Fraction]:
    sys = design.system
    core = _frobenius_up(sys.A - design.K @ sys.C) * e_bound + _frobenius_up(sys.B - design.K @ sys.D) * w_bound
    n_levels = len(design.S)
    return [core * (_frobenius_up(design.M[k + 1]) if k + 1 < n_levels else 1) for k in range(n_levels)]


def _read_bounds(w_bound: Any, e_bound: Any, theta: Any) -> tuple[Fraction, Fraction, Fraction]:
    w = exact_fraction(w_bound, "w_bound")
    if e_bound is None:
        raise for_option(DomainError("w_bound needs e_bound: a bound of ‖x − x̃‖ after the Luenberger transient "
                                     "(the paper's ẽ⁺, (11))"), "e_bound")
    e = exact_fraction(e_bound, "e_bound")
    th = DEFAULT_THETA if theta is None else exact_fraction(theta, "theta")
    if w < 0 or e <= 0:
        raise for_option(DomainError(f"w_bound = {w} must be ≥ 0 and e_bound = {e} > 0"),
                         "w_bound" if w < 0 else "e_bound")
    if not 0 < th < 1:
        raise for_option(DomainError(f"theta = {th} must lie in (0, 1)"), "theta")
    return w, e, th


def sta_gain_condition(design: Any, *, w_bound: Any, e_bound: Any, theta: Any = None) -> STAGainReport:
    """Check the gains of a :class:`~uio_ring.design.hierarchical_sta.HierarchicalSTADesign`
    against (16)/(21) for ``‖w‖ ≤ w_bound`` and ``‖x − x̃‖ ≤ e_bound``, exactly."""
    w, e, th = _read_bounds(w_bound, e_bound, theta)
    levels = []
    for k, (beta, (lam, alpha)) in enumerate(zip(_betas(design, w, e), design.gains, strict=True), start=1):
        ok = alpha > beta and lam * lam * (alpha - beta) * (1 - th) ** 2 > 2 * (alpha + beta) ** 2 * (1 + th) ** 2
        levels.append(LevelMargin(k, beta, alpha, lam, ok))
    bad = [lv.level for lv in levels if not lv.holds]
    reason = "" if not bad else (f"level(s) {bad} do not satisfy the sufficient condition (it is conservative: "
                                 "the observer may converge anyway; check in simulation)")
    return STAGainReport(tuple(levels), w, e, th, not bad, reason)


def _round_up(x: Fraction, den: int = 100) -> Fraction:
    return Fraction(-(-x.numerator * den // x.denominator), den)


def gains_from_bounds(design: Any, *, w_bound: Any, e_bound: Any, theta: Any = None) -> tuple[tuple[Fraction, Fraction], ...]:
    """``(λ_k, α_k)`` satisfying (16)/(21) with margin: ``α_k = 2 β_k`` (at least 1/100) and
    ``λ_k`` the right side of (16)/(21) rounded up to hundredths, plus 1/100."""
    w, e, th = _read_bounds(w_bound, e_bound, theta)
    out = []
    for beta in _betas(design, w, e):
        alpha = max(_round_up(2 * beta), Fraction(1, 100))
        lam = _round_up(lambda_needed(alpha, beta, th)) + Fraction(1, 100)
        out.append((lam, alpha))
    return tuple(out)
