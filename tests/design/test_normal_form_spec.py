"""The example spec examples/aircraft_normal_form.yaml: its system is paper 000's aircraft and its
``design:`` keys are the arguments of design_normal_form (read here with plain YAML, independent
of the spec layer, which wires ``method: normal-form``)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import yaml

from design import paper000
from uio_ring import DelaySystem, design_normal_form

SPEC = Path(__file__).resolve().parents[2] / "examples" / "aircraft_normal_form.yaml"


def _exact(x):
    return Fraction(str(x))


def test_example_spec_is_the_aircraft_and_designs():
    data = yaml.safe_load(SPEC.read_text(encoding="utf-8"))
    s = data["system"]
    sys = DelaySystem([[str(x) for x in r] for r in s["A"]], s["B"], s["C"], None, E=s["E"],
                      state_names=s["states"], output_names=s["outputs"],
                      unknown_input_names=s["unknown_inputs"], known_input_names=s["known_inputs"])
    ref = paper000.aircraft()
    assert sys.A == ref.A and sys.B == ref.B and sys.C == ref.C and sys.E == ref.E
    design = dict(data["design"])
    assert design.pop("method") == "normal-form"
    d = design_normal_form(sys, [str(x) for x in design.pop("input_bounds")], **design)
    assert d.mu == (4, 3) and d.certificate().ok
    for ks, printed in zip(d.kappa, paper000.GAINS_89, strict=True):
        assert all(abs(k - Fraction(p)) <= Fraction(6, 100000) for k, p in zip(ks, printed, strict=True))
    assert [_exact(x) for x in data["simulate"]["phi"]] == [_exact(x) for x in paper000.X0]
