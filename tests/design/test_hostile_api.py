"""The Python API fails the way the command line does: the package's own errors (issue 16 §4)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from uio_ring import DelaySystem, PolyMatrix, design_zheng_bejarano
from uio_ring.errors import DimensionError, DomainError, UioRingError


def small() -> DelaySystem:
    return DelaySystem("[[0, 1], [-1, -d]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)


@pytest.mark.parametrize(
    "poles",
    [[np.float64(-0.1)], np.array([-0.1]), np.array([-0.1], dtype=np.float32), [np.int64(-1) / 10], ["-0.1"]],
    ids=["np.float64", "float64 array", "float32 array", "np.int64 quotient", "text"],
)
def test_numpy_poles_follow_the_decimal_text_rule(poles):
    design = design_zheng_bejarano(small(), poles=poles)
    assert design.poles == (Fraction(-1, 10),)
    assert design.certificate().ok


BAD = [
    (lambda: design_zheng_bejarano(small(), poles={-1}), DomainError, "poles must be a list of rationals"),
    (lambda: design_zheng_bejarano(small(), poles=[None]), DomainError, r"poles\[0\]: cannot read"),
    (lambda: design_zheng_bejarano(small(), poles=[float("nan")]), DomainError, "not a finite number"),
    (lambda: design_zheng_bejarano(small(), poles=["1e99999999"]), DomainError, "more than 1000 digits"),
    (lambda: DelaySystem(PolyMatrix.zeros(0, 0), PolyMatrix.zeros(0, 1), PolyMatrix.zeros(1, 0), None),
     DimensionError, "a system without states"),
    (lambda: DelaySystem([[0.0, 1.0], [-1.0, -2.0]], np.array([0.0, 1.0]), np.eye(2), None), DimensionError,
     "1-dimensional array"),
    (lambda: DelaySystem({0: [[1]]}, "[[1]]", "[[1]]", None), DimensionError, "dict has no order"),
    (lambda: DelaySystem("[[0]]", "[[1]]", "[[1]]", None, state_names={"a"}), DomainError, "list of names"),
]


@pytest.mark.parametrize("call,cls,pattern", BAD)
def test_bad_api_input_raises_package_errors(call, cls, pattern):
    with pytest.raises(cls, match=pattern) as info:
        call()
    assert isinstance(info.value, UioRingError)


def test_numpy_system_matrices_are_read_exactly():
    sys = DelaySystem(np.array([[0.0, 1.0], [-1.0, -0.1]]), np.array([[0.0], [1.0]]), np.eye(2), None)
    assert sys.A == PolyMatrix("[[0, 1], [-1, -1/10]]")


MORE = [
    (lambda: PolyMatrix([[1]]) * np.array([1]), DomainError, r"an array of shape \(1,\) is not a number"),
    (lambda: PolyMatrix([[np.array([1.0])]]), DomainError, "is not a number"),
    (lambda: PolyMatrix("d")[0, 0] ** 10**9, DomainError, "MAX_POWER_DEGREE"),
]


@pytest.mark.parametrize("call,cls,pattern", MORE)
def test_more_api_misuse(call, cls, pattern):
    with pytest.raises(cls, match=pattern):
        call()


def test_loaders_refuse_non_paths_and_bytes():
    from uio_ring.errors import SpecError
    from uio_ring.spec import load_design, load_spec, load_spec_text

    for call in (lambda: load_spec(None), lambda: load_design(3), lambda: load_spec_text(b"system: 1")):
        with pytest.raises(SpecError):
            call()


@pytest.mark.parametrize("h", ["1e99999999", Fraction(10**400)], ids=["huge text", "huge Fraction"])
def test_simulation_numbers_are_bounded_before_use(h):
    from uio_ring.errors import SimulationError
    from uio_ring.sim import simulate_observer

    sys = DelaySystem("[[0, 1], [-1, -d]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None, h="0.1")
    with pytest.raises(SimulationError, match="digits|beyond float64"):
        simulate_observer(design_zheng_bejarano(sys, poles=[-2]), sys, h=h, t_final=1, dt=0.1)
