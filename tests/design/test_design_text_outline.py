"""``str(DelayUIODesign)`` prints small matrices in full and outlines large ones (shape,
δ-degree, coefficient bits) instead of megabytes of text."""

from __future__ import annotations

from uio_ring import DelaySystem, design_zheng_bejarano
from uio_ring.design import delay_uio_design as dud


def _design():
    sys = DelaySystem("[[0, 1], [d, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", "[[0], [0]]")
    return design_zheng_bejarano(sys, poles=[-1])


def test_small_matrices_printed_in_full():
    des = _design()
    text = str(des)
    assert "not shown" not in text
    assert "  T_left_inverse =\n    " + str(des.T_left_inverse).replace("\n", "\n    ") in text


def test_large_matrices_outlined_with_shape_and_degree(monkeypatch):
    des = _design()
    monkeypatch.setattr(dud, "TEXT_MATRIX_CHARS", 0)  # every nonempty matrix counts as large
    text = str(des)
    M = des.T_left_inverse
    line = next(ln for ln in text.splitlines() if ln.startswith("  T_left_inverse:"))
    assert f"{M.rows}×{M.cols}, δ-degree {M.degree()}" in line
    assert "T_left_inverse =" not in text
