"""Can the high-gain observer of Grip & Saberi (2010) be designed for a system?  One report.

The method is for ``x' = A x + E u + φ(t, x)``, ``y = C x + F u``: delay-free,
no unknown input ``w`` entering (``B = 0`` and ``D = 0``; an unknown
nonlinearity is described by the ``W_k`` of its Jacobian instead), ``rank C = p``
and (A, C) observable.  Whether the ``W_k`` are admissible, or can be made so by
output shaping, is the design's business (it needs the ``W_k``).

>>> from uio_ring import DelaySystem
>>> high_gain_applicable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [0]]", "[[1, 0]]", None)).holds
True
>>> print(high_gain_applicable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None)).reason)
the unknown input w enters the system (B ≠ 0 or D ≠ 0); the high-gain observer estimates x of x' = A x + φ(t, x) without unknown inputs: describe the uncertainty by the W_k of φ instead
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from uio_ring.analysis.canonical_form import observability_indices_of
from uio_ring.analysis.report import Report
from uio_ring.ring import constant as qc
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["HighGainApplicability", "high_gain_applicable"]


@dataclass(frozen=True)
class HighGainApplicability(Report):
    """Verdict of :func:`high_gain_applicable` (``holds``, ``reason``, ``summary``,
    and the observability indices of (A, C) when they were computed)."""

    holds: bool
    reason: str
    observability_indices: tuple[int, ...] = ()

    @property
    def name(self) -> str:
        return "high-gain observer (Grip & Saberi 2010) applicability"

    @property
    def summary(self) -> str:
        if not self.holds:
            return f"high-gain: skipped — {self.reason}"
        return f"high-gain: applies — (A, C) observable with indices {self.observability_indices}"

    def _detail_lines(self) -> list[str]:
        return [f"observability indices of (A, C): {self.observability_indices}"] if self.holds else []

    def to_dict(self) -> dict[str, Any]:
        return {"method": "high-gain", "holds": self.holds, "reason": self.reason,
                "observability_indices": list(self.observability_indices)}


def high_gain_applicable(sys: DelaySystem) -> HighGainApplicability:
    """Check the system-level assumptions of the high-gain observer; never raises on failure.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> high_gain_applicable(DelaySystem("[[0, 0], [0, 0]]", "[[0], [0]]", "[[1, 0]]", None)).reason
    '(A, C) is not observable (observability indices (1,), rank 1 < n = 2)'
    """
    if not sys.is_delay_free:
        return HighGainApplicability(False, f"the system has delays (δ-degree {sys.max_delay_degree}); the "
                                            "high-gain observer is for delay-free systems")
    if not (sys.B.is_zero() and sys.D.is_zero()):
        return HighGainApplicability(False, "the unknown input w enters the system (B ≠ 0 or D ≠ 0); the high-gain "
                                            "observer estimates x of x' = A x + φ(t, x) without unknown inputs: "
                                            "describe the uncertainty by the W_k of φ instead")
    A, C = qc.qmat(sys.A, "A"), qc.qmat(sys.C, "C")
    p, n = C.nrows(), A.nrows()
    if qc.qrank(C) < p:
        return HighGainApplicability(False, f"C has rank {qc.qrank(C)} < {p} outputs (remove dependent outputs)")
    q = observability_indices_of(A, C)
    if sum(q) < n:
        return HighGainApplicability(False, f"(A, C) is not observable (observability indices {q}, "
                                            f"rank {sum(q)} < n = {n})", q)
    return HighGainApplicability(True, "", q)
