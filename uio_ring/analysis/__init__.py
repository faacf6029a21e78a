"""Analysis layer: structural properties of delay systems (exact, over Q[δ])."""

from uio_ring.analysis.assumptions import check_assumptions
from uio_ring.analysis.observability import unknown_input_observability
from uio_ring.analysis.rank_condition import check_rank_condition, matching_matrix
from uio_ring.analysis.report import AssumptionsReport, ObservabilityReport, RankConditionReport

__all__ = [
    "AssumptionsReport",
    "ObservabilityReport",
    "RankConditionReport",
    "check_assumptions",
    "check_rank_condition",
    "matching_matrix",
    "unknown_input_observability",
]
