"""Design files write a derived field (``Ō_{l*}`` of a Zheng–Bejarano design) as
``$derived`` and rebuild it exactly; the summary outlines large matrices; a design's
certificate and noise figures are computed once per object."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from uio_ring.design.delay_uio_design import krylov_matrix
from uio_ring.design.methods import design_auto
from uio_ring.errors import SpecError
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.spec import designs as sd
from uio_ring.spec import load_design, load_spec, save_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def design():
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    return design_auto(spec.system, **spec.design.options).design


def test_krylov_matrix_is_the_stacked_powers(design):
    r, l = design.r, design.l_star
    A = design.A_bar
    O = krylov_matrix(design.C_bar, A, l)
    power = PolyMatrix.identity(A.rows)
    for k in range(l):
        assert O[k * r:(k + 1) * r, :] == design.C_bar @ power
        power = power @ A
    assert O == design.O


@pytest.mark.parametrize("certify_first", [False, True])
def test_derived_O_round_trip(tmp_path, design, certify_first):
    fresh = dataclasses.replace(design)  # no memo: the derivation is compared exactly
    if certify_first:
        assert fresh.certificate().ok and fresh.certified()
    else:
        assert not fresh.certified()
    (p,) = save_design(fresh, tmp_path / "d", formats=("json",))
    data = json.loads(p.read_text())
    assert data["fields"]["O"] == {"$derived": type(design).derived_fields["O"], "shape": list(design.O.shape)}
    again = load_design(p)
    assert again == design and again.O == design.O


def test_an_O_that_is_not_the_krylov_matrix_is_written_in_full(tmp_path, design):
    wrong = dataclasses.replace(design, O=design.O + PolyMatrix.identity(design.O.rows)[:, : design.O.cols])
    assert not wrong.certificate().ok
    data = sd.design_to_data(dataclasses.replace(wrong))
    assert "$matrix" in data["fields"]["O"]
    (p,) = save_design(wrong, tmp_path / "w", formats=("json",))
    assert load_design(p, verify=False).O == wrong.O


def _edited(tmp_path, design, edit):
    (p,) = save_design(design, tmp_path / "e", formats=("json",))
    data = json.loads(p.read_text())
    edit(data["fields"])
    p.write_text(json.dumps(data))
    return p


@pytest.mark.parametrize(("edit", "message"), [
    (lambda f: f.update(T={"$derived": "x", "shape": [6, 4]}), r"'T' of a DelayUIODesign is not derived"),
    (lambda f: f["O"].update(shape=[5, 4]), r"does not give the 5 rows"),
    (lambda f: f["O"].update(shape=[6, 99999]), r"shape .* is not two whole numbers"),
    (lambda f: f.update(l_star=10**6), r"l_star = 1000000 does not give"),
])
def test_hostile_derived_fields_are_refused(tmp_path, design, edit, message):
    with pytest.raises(SpecError, match=message):
        load_design(_edited(tmp_path, design, edit))


def test_summary_outlines_large_matrices(tmp_path, design, monkeypatch):
    monkeypatch.setattr(sd, "SUMMARY_MATRIX_CHARS", 150)
    data = sd.design_to_data(design)
    outlines = {k: v for k, v in data["summary"]["matrices"].items() if isinstance(v, dict)}
    assert "O" in outlines and "C0" not in outlines  # C0 = [I, 0] of zheng2015 is small
    for name, outline in outlines.items():
        M = getattr(design, name)
        assert outline["shape"] == list(M.shape) and outline["degree"] == M.degree()
        assert outline["coefficient_bits"] == max(
            (max(p.numer().height_bits(), p.denom().bit_length()) for row in M._r for p in row if not p.is_zero()),
            default=0)
    full = {k: v for k, v in data["summary"]["matrices"].items() if not isinstance(v, dict)}
    assert full == {k: v for k, v in design.to_dict()["matrices"].items() if k in full}
    (p,) = save_design(design, tmp_path / "s", formats=("yaml",))
    assert load_design(p) == design


def test_certificate_and_performance_are_computed_once_per_design(design):
    fresh = dataclasses.replace(design)
    assert fresh.certificate() is fresh.certificate()
    assert fresh.performance() is fresh.performance(h=fresh.system.h)
    assert fresh.performance(tolerance=1e-2) is not fresh.performance()
    assert dataclasses.replace(fresh).certified() is False  # the memo is per object


def test_derivation_is_bounded_before_the_products():
    """``derive_field`` refuses an Ō whose δ-degree would pass the parser's bound, and an l*
    outside 1 … n, before multiplying."""
    from uio_ring.design.delay_uio_design import DelayUIODesign
    from uio_ring.ring.parse import MAX_DEGREE

    C = PolyMatrix("[[d, 0]]")
    A = PolyMatrix(f"[[0, d**{MAX_DEGREE}], [1, 0]]")
    with pytest.raises(ValueError, match="δ-degree above"):
        DelayUIODesign.derive_field("O", {"C_bar": C, "A_bar": A, "l_star": 2})
    with pytest.raises(ValueError, match="l_star = 3 does not give"):
        DelayUIODesign.derive_field("O", {"C_bar": C, "A_bar": A, "l_star": 3})
    assert DelayUIODesign.derive_field("O", {"C_bar": C, "A_bar": A, "l_star": 1}) == C
