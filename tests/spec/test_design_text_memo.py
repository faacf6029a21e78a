"""A design file writes each matrix's text once (``matrix_text_memo``): the data is the data
of the plain path, and no list is shared between two places (YAML would write aliases)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from uio_ring.design.base import matrix_text_memo, matrix_to_data
from uio_ring.design.methods import design_auto
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.spec import load_spec
from uio_ring.spec.designs import _encode, design_to_data
from uio_ring.spec.yaml_io import dump_yaml, load_yaml_text

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("name", ["zheng2015.yaml", "two_masses_delay_free.yaml", "aircraft_normal_form.yaml"])
def test_design_data_is_the_plain_paths_data(name):
    spec = load_spec(EXAMPLES / name)
    design = design_auto(spec.system, **spec.design.options).design
    plain_fields = {f.name: _encode(getattr(design, f.name)) for f in dataclasses.fields(design)
                    if f.compare and f.name not in type(design).derived_fields}
    plain_summary = design.to_dict()  # outside any memo: str of every coefficient
    data = design_to_data(design)
    derived = {k: v for k, v in data["fields"].items() if k in type(design).derived_fields}
    assert all("$derived" in v for v in derived.values())
    assert {k: v for k, v in data["fields"].items() if k not in derived} == plain_fields
    assert data["summary"] == plain_summary  # the examples' matrices are small: written in full
    text = dump_yaml(data)
    assert "&id" not in text and "*id" not in text  # no anchors: nothing shared
    assert load_yaml_text(text, max_bytes=len(text.encode()) + 1)["fields"] == data["fields"]


def test_memo_reuses_text_per_matrix_object_only():
    A, B = PolyMatrix("[[d, 1]]"), PolyMatrix("[[2*d, 1/3]]")
    with matrix_text_memo():
        a1, b1, a2 = matrix_to_data(A), matrix_to_data(B), matrix_to_data(A)
        a2[0][0] = "changed"  # the caller owns its lists: the memo is untouched
        a3 = matrix_to_data(A)
    assert a1 == a3 == [["d", "1"]] and b1 == [["2*d", "1/3"]]
    assert matrix_to_data(A) == [["d", "1"]]  # outside: the plain path
