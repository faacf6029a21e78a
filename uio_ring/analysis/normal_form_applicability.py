"""Can the observer normal form of Niederwieser et al. (2022) be used?  One report, for ``auto``.

Conditions (Niederwieser et al. 2022, Assumptions 2.2–2.3, with the feed-through reduction of
Appendix A): the system is delay-free, its unknown-input columns are
independent (``rank [B; D] = n_w``), and it is strongly observable.  The
input bounds (Assumption 2.1) are asked for by the design itself.

The report also says whether the rank (observer-matching) condition holds —
not needed here, but it is why Zheng et al.'s observer may refuse a system this
method accepts (the aircraft example of Niederwieser et al. (2022) has ``C B = 0``).

>>> from uio_ring import DelaySystem
>>> rep = normal_form_applicable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))
>>> rep.holds, rep.matching_condition
(True, False)
>>> print(normal_form_applicable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None)).reason)
not strongly observable: invariant zero(s): roots of s ≈ {0}
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from uio_ring.analysis.report import Report
from uio_ring.analysis.strong_observability import (
    StrongObservabilityReport,
    constant_matrices,
    is_strongly_observable,
)
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["NormalFormApplicability", "normal_form_applicable"]


@dataclass(frozen=True)
class NormalFormApplicability(Report):
    """Verdict: does the observer normal form (Niederwieser et al. 2022) apply to this system?

    Attributes
    ----------
    holds
        All conditions hold.
    reason
        The first failed condition, in words (empty when it holds).
    delay_free, independent_inputs
        δ-degree 0; ``rank [B; D] = n_w``.
    strong_observability
        The :class:`~uio_ring.analysis.strong_observability.StrongObservabilityReport`
        (``None`` when the system has delays).
    matching_condition
        ``rank [[CB, D], [D, 0]] = rank D + rank [B; D]`` (informative; ``None`` with delays).
    """

    holds: bool
    reason: str
    delay_free: bool
    independent_inputs: bool
    strong_observability: StrongObservabilityReport | None
    matching_condition: bool | None

    @property
    def name(self) -> str:
        return "observer normal form (Niederwieser et al. 2022) applicability"

    @property
    def summary(self) -> str:
        """One line for ``auto``: why this method was chosen or skipped."""
        if not self.holds:
            return f"normal-form: skipped — {self.reason}"
        extra = "" if self.matching_condition else "; the matching condition fails, which this method does not need"
        return f"normal-form: applies — strongly observable (no invariant zeros, left invertible){extra}"

    def _detail_lines(self) -> list[str]:
        lines = [] if self.strong_observability is None else [str(self.strong_observability)]
        if self.matching_condition is not None:
            lines.append(f"matching condition: {'holds' if self.matching_condition else 'fails (not needed)'}")
        return lines

    def _detail_html(self) -> str:
        return "" if self.strong_observability is None else self.strong_observability._repr_html_()

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": "normal-form",
            "holds": self.holds,
            "reason": self.reason,
            "delay_free": self.delay_free,
            "independent_inputs": self.independent_inputs,
            "matching_condition": self.matching_condition,
            "strong_observability": None if self.strong_observability is None else self.strong_observability.to_dict(),
        }


def normal_form_applicable(sys: DelaySystem) -> NormalFormApplicability:
    """Check the assumptions of Niederwieser et al.'s observer normal form; never raises on failure.

    Parameters
    ----------
    sys
        Any :class:`~uio_ring.systems.DelaySystem`.

    Returns
    -------
    NormalFormApplicability
        ``holds``, ``reason``, ``summary`` (a line for ``auto``) and the
        strong-observability report.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> normal_form_applicable(DelaySystem("[[d]]", "[[1]]", "[[1]]", None)).reason
    'the system has delays (δ-degree 1); the observer normal form is for delay-free systems'
    """
    if not sys.is_delay_free:
        return NormalFormApplicability(
            False,
            f"the system has delays (δ-degree {sys.max_delay_degree}); the observer normal form is for delay-free systems",
            False, False, None, None,
        )
    M = constant_matrices(sys)
    B, C, D = M["B"], M["C"], M["D"]
    m = sys.n_w
    rBD = QMatrix.vstack(B, D).rank()
    rD = D.rank()
    rM = QMatrix.block([[C @ B, D], [D, QMatrix.zeros(sys.n_y, m)]]).rank()
    matching = rM == rD + rBD
    so = is_strongly_observable(sys, cross_check=False)
    indep = rBD == m
    if not indep:
        reason = (
            f"the unknown-input columns are dependent: rank [B; D] = {rBD} < n_w = {m}; "
            "combine the unknown inputs into independent ones first"
        )
    elif not so.holds:
        reason = f"not strongly observable: {so.reason}"
    else:
        reason = ""
    return NormalFormApplicability(not reason, reason, True, indep, so, matching)
