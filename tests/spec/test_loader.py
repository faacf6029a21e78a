"""Spec loading: exact numbers, the forms of matrices, and the shipped examples."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from uio_ring import PolyMatrix
from uio_ring.spec import load_spec, load_spec_text, schema

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

PAPER_A = PolyMatrix("[[0, -1, 1, 0], [-1, d, 0, 0], [1, 0, 1, 0], [d, 1, 1, -1]]")


def test_decimal_text_is_read_exactly():
    spec = load_spec_text(
        """
system:
  A: [[0.1, 1e-3], [-2.5, 0]]
  B: [[0], [1]]
  C: [[1, 0]]
  h: 0.01
"""
    )
    assert spec.system.h == Fraction(1, 100)
    assert spec.system.A == PolyMatrix([["1/10", "1/1000"], ["-5/2", 0]])


def test_three_forms_of_a_matrix_agree():
    rows = "[[0, -1, 1, 0], [-1, d, 0, 0], [1, 0, 1, 0], [d, 1, 1, -1]]"
    coeffs = "{0: [[0, -1, 1, 0], [-1, 0, 0, 0], [1, 0, 1, 0], [0, 1, 1, -1]], 1: [[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [1, 0, 0, 0]]}"
    for form in (rows, f'"{rows}"', coeffs):
        spec = load_spec_text(f"system:\n  A: {form}\n  B: [[0], [0], [1], [0]]\n  C: [[1, 0, 0, 0]]\n  h: 1\n")
        assert spec.system.A == PAPER_A, form


def test_delta_symbol_and_d_are_the_same():
    a = load_spec_text("system: {A: [['δ']], B: [[1]], C: [[1]], h: 1}")
    b = load_spec_text("system: {A: [[d]], B: [[1]], C: [[1]], h: 1}")
    assert a.system.A == b.system.A


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_every_shipped_example_loads(name):
    spec = load_spec(EXAMPLES / name)
    assert spec.system.n_x > 0 and spec.name


def test_paper_example_spec_is_the_paper_system():
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    s = spec.system
    assert s.A == PAPER_A
    assert s.D == PolyMatrix("[[1, d], [0, 0], [1, d]]")
    assert s.h == Fraction(1, 100)
    assert spec.design.method == "zheng-bejarano"
    assert spec.design.options["poles"] == (-10, -25, -50)
    assert spec.simulate is not None and spec.simulate.h / spec.simulate.dt == 10


def test_h01_example_differs_only_in_h():
    a, b = load_spec(EXAMPLES / "zheng2015.yaml"), load_spec(EXAMPLES / "zheng2015_h01.yaml")
    assert b.system.h == Fraction(1, 10)
    assert a.system.matrices() == b.system.matrices()


def test_signals_evaluate_on_arrays():
    import numpy as np

    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    t = np.array([0.0, np.pi / 200])
    w = spec.simulate.signal("w")(t)
    assert w.shape == (2, 2)
    assert w[0, 1] == pytest.approx(-10.0) and w[1, 0] == 0.0


def test_schema_is_valid_json_schema():
    import jsonschema

    jsonschema.Draft202012Validator.check_schema(schema())
