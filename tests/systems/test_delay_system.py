"""DelaySystem: construction, validation, sizes, conversions (uio_ring.systems)."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest

from uio_ring import DelaySystem, DimensionError, DomainError, PolyMatrix, delay_system

A2 = "[[0, 1], [-1, d]]"


def test_accepts_strings_lists_and_polymatrix():
    s1 = DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", "[[0]]")
    s2 = DelaySystem([[0, 1], [-1, "d"]], [[0], [1]], [[1, 0]], [[0]])
    s3 = DelaySystem(PolyMatrix(A2), PolyMatrix("[[0], [1]]"), PolyMatrix("[[1, 0]]"), None)
    s4 = DelaySystem("[[0, 1], [-1, δ]]", "[[0], [1]]", "[[1, 0]]", None)
    assert s1 == s2 == s3 == s4
    assert isinstance(s1.A, PolyMatrix) and s1.D == PolyMatrix.zeros(1, 1)


def test_sizes_and_degree():
    s = DelaySystem(A2, "[[0], [1]]", "[[1, 0], [0, d**2]]", None, E="[[1, 0], [0, 1]]")
    assert (s.n_x, s.n_w, s.n_u, s.n_y) == (2, 1, 2, 2)
    assert s.max_delay_degree == 2 and not s.is_delay_free
    assert s.F == PolyMatrix.zeros(2, 2)
    free = s.at_delta(0)
    assert free.is_delay_free and free.max_delay_degree == 0
    assert free.C == PolyMatrix("[[1, 0], [0, 0]]")


def test_from_coefficients_is_form_1():
    s = DelaySystem.from_coefficients(
        A=[[[0, 1], [-1, 0]], [[0, 0], [0, 1]]], B=[[[0], [1]]], C=[[[1, 0]]], h="0.1"
    )
    assert s.A == PolyMatrix(A2)
    assert s.D == PolyMatrix.zeros(1, 1)
    assert s.h == Fraction(1, 10)


def test_h_is_exact():
    assert DelaySystem("[[0]]", "[[1]]", "[[1]]", None, h=0.1).h == Fraction(1, 10)
    assert DelaySystem("[[0]]", "[[1]]", "[[1]]", None, h="1/3").h == Fraction(1, 3)
    assert DelaySystem("[[0]]", "[[1]]", "[[1]]", None).h is None


@pytest.mark.parametrize(
    "args, kwargs, exc, match",
    [
        (("[[0, 1]]", "[[1]]", "[[1, 0]]", None), {}, DimensionError, r"A is 1×2; it must be square"),
        ((A2, "[[0], [1], [2]]", "[[1, 0]]", None), {}, DimensionError, r"B has 3 rows; expected 2 \(= rows of A\)"),
        ((A2, "[[0], [1]]", "[[1, 0, 0]]", None), {}, DimensionError, r"C has 3 columns; expected 2"),
        ((A2, "[[0], [1]]", "[[1, 0]]", "[[0, 0]]"), {}, DimensionError, r"D is 1×2; expected 1×1"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None, "[[1]]"), {}, DimensionError, r"E has 1 rows; expected 2"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None, "[[1], [0]]", "[[1, 2]]"), {}, DimensionError, r"F has 2 columns; expected 1"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None), {"h": 0}, DomainError, r"h = 0 must be positive"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None), {"state_names": ["a"]}, DimensionError, r"state_names has 1 names; expected 2"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None), {"state_names": ["a.b", "c"]}, DomainError, r"contains '\.'"),
        ((A2, "[[0], [1]]", "[[1, 0]]", None), {"output_names": ["y", "z"]}, DimensionError, r"output_names"),
        (("[[0, 1], [-1, sqrt(2)]]", "[[0], [1]]", "[[1, 0]]", None), {}, Exception, r"^A: "),
    ],
)
def test_errors_name_the_matrix(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        DelaySystem(*args, **kwargs)


def test_names_default_and_custom():
    s = DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", None)
    assert s.state_names == ("x[0]", "x[1]") and s.output_names == ("y[0]",)
    assert s.unknown_input_names == ("w[0]",) and s.known_input_names == ()
    t = delay_system(A2, "[[0], [1]]", "[[1, 0]]", states=["p", "v"], unknown_inputs=["f"])
    assert t.state_names == ("p", "v") and t.unknown_input_names == ("f",)


def test_frozen_and_hashable():
    s = DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", None)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.A = PolyMatrix("[[1]]")  # type: ignore[misc]
    assert hash(s) == hash(DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", None))


def test_no_unknown_input_and_empty_lists():
    s = DelaySystem(A2, [[], []], "[[1, 0]]", None)
    assert s.n_w == 0 and s.D.shape == (1, 0)


def test_dict_round_trip():
    s = DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", "[[1/2]]", E="[[1], [d]]", h="1/100",
                    state_names=["p", "v"])
    assert DelaySystem.from_dict(s.to_dict()) == s
    assert s.to_dict()["A"] == [["0", "1"], ["-1", "d"]]


def test_display():
    s = DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", None, h="1/10")
    assert "δ-degree 1" in str(s) and "h=1/10" in str(s)
    assert r"\delta" in s._repr_latex_()
    assert repr(s).startswith("DelaySystem(A=PolyMatrix(")


def test_to_control_delay_free():
    control = pytest.importorskip("control")
    s = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None, E="[[0], [1]]",
                    state_names=["p", "v"])
    ss = s.to_control()
    assert isinstance(ss, control.StateSpace)
    assert ss.nstates == 2 and ss.ninputs == 2 and ss.noutputs == 1
    assert list(ss.state_labels) == ["p", "v"]
    assert float(ss.A[1, 0]) == -2.0


def test_to_control_refuses_delays():
    with pytest.raises(DomainError, match="delay-free"):
        DelaySystem(A2, "[[0], [1]]", "[[1, 0]]", None).to_control()
