"""One base for the verdict reports: ``holds``, ``reason`` and the display written once."""

from __future__ import annotations

import pytest

from uio_ring import DelaySystem
from uio_ring.analysis import (
    Report,
    check_assumptions,
    check_rank_condition,
    is_strong_star_detectable,
    is_strongly_detectable,
    is_strongly_observable,
    normal_form_applicable,
    observability_indices,
    relative_degrees,
    unknown_input_observability,
)
from uio_ring.analysis.molinari import molinari_sequence

#: strongly observable, CB = 0 (the rank condition fails); y = x_1 only
SYS = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None)
#: an invariant zero at 0: y = x_2
ZERO = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None)

CHECKS = [
    unknown_input_observability,
    check_rank_condition,
    check_assumptions,
    is_strongly_observable,
    is_strongly_detectable,
    is_strong_star_detectable,
    normal_form_applicable,
    relative_degrees,
    observability_indices,
    molinari_sequence,
]


@pytest.mark.parametrize("check", CHECKS, ids=[c.__name__ for c in CHECKS])
@pytest.mark.parametrize("sys", [SYS, ZERO], ids=["SYS", "ZERO"])
def test_every_report_shares_the_base(check, sys):
    rep = check(sys)
    assert isinstance(rep, Report) and isinstance(rep.holds, bool) and not hasattr(rep, "ok")
    text, page = str(rep), rep._repr_html_()
    assert text.startswith(f"{rep.name}: {'holds' if rep.holds else 'FAILS'}")
    assert page.startswith("<b>")
    if rep.holds:
        assert rep.reason == "" and "reason:" not in text.splitlines()[-1]
    else:
        assert rep.reason and text.endswith(f"reason: {rep.reason}") and "reason: " in page


def test_verdicts():
    assert not check_rank_condition(SYS).holds and is_strongly_observable(SYS).holds
    assert not is_strongly_observable(ZERO).holds and "invariant zero" in is_strongly_observable(ZERO).reason
    assert normal_form_applicable(SYS).holds and not normal_form_applicable(ZERO).holds
