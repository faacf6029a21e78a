"""Both assumptions of Zheng et al. (2015) at once (what a design method checks first).

>>> from uio_ring import DelaySystem
>>> rep = check_assumptions(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))
>>> rep.holds, rep.failed
(False, ('Assumption 2',))
"""

from __future__ import annotations

from uio_ring.analysis.observability import unknown_input_observability
from uio_ring.analysis.rank_condition import check_rank_condition
from uio_ring.analysis.report import AssumptionsReport
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["check_assumptions"]


def check_assumptions(sys: DelaySystem) -> AssumptionsReport:
    """Assumption 1 (:func:`unknown_input_observability`) and Assumption 2
    (:func:`check_rank_condition`) of Zheng et al. (2015), as one report.

    Parameters
    ----------
    sys
        The delay system.

    Returns
    -------
    AssumptionsReport
        ``holds`` iff both hold; ``failed`` names the failed ones and
        ``reason`` explains them.  Never raises because an assumption fails.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> check_assumptions(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)).holds
    True
    """
    return AssumptionsReport(
        observability=unknown_input_observability(sys),
        rank_condition=check_rank_condition(sys),
    )
