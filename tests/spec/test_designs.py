"""Design files: exact round trip through JSON and YAML."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from uio_ring.design.methods import design_auto
from uio_ring.errors import SpecError
from uio_ring.spec import load_design, load_spec, save_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("name", ["zheng2015.yaml", "two_masses_delay_free.yaml"])
def test_round_trip_gives_an_equal_design(tmp_path, name):
    spec = load_spec(EXAMPLES / name)
    design = design_auto(spec.system, **spec.design.options).design
    paths = save_design(design, tmp_path / "d", formats=("json", "yaml", "latex"))
    assert [p.suffix for p in paths] == [".json", ".yaml", ".tex"]
    for p in paths[:2]:
        again = load_design(p)
        assert again == design
        assert again.certificate().ok
    # exact values are strings, never floats
    data = json.loads(paths[0].read_text())
    assert data["fields"]["poles"] == {"$tuple": [{"$q": str(p)} for p in design.poles]}


def test_not_a_design_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text('{"a": 1}')
    with pytest.raises(SpecError, match="not a uio_ring design file"):
        load_design(p)


def test_design_file_with_a_missing_field(tmp_path):
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    design = design_auto(spec.system, **spec.design.options).design
    (p,) = save_design(design, tmp_path / "d", formats=("json",))
    data = json.loads(p.read_text())
    del data["fields"]["T"]
    p.write_text(json.dumps(data))
    with pytest.raises(SpecError, match="no field 'T'"):
        load_design(p)


def test_normal_form_design_round_trip(tmp_path):
    spec = load_spec(EXAMPLES / "aircraft_normal_form.yaml")
    design = design_auto(spec.system, **spec.design.options).design
    assert design.method == "normal-form"
    for p in save_design(design, tmp_path / "nf", formats=("json", "yaml")):
        again = load_design(p)
        assert again == design and again.certificate().ok


def test_options_of_another_method_are_refused():
    from uio_ring.spec import load_spec_text

    with pytest.raises(SpecError, match=r"design\.poles: option\(s\) poles do not apply to method 'normal-form'"):
        load_spec_text("system: {A: [[0]], B: [[1]], C: [[1]]}\ndesign: {method: normal-form, input_bounds: 1, poles: [-1]}\n")
    with pytest.raises(SpecError, match=r"design\.input_bounds: method 'normal-form' needs input_bounds"):
        load_spec_text("system: {A: [[0]], B: [[1]], C: [[1]]}\ndesign: {method: normal-form}\n")
