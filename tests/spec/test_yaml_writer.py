"""The design files' YAML writer: any plain data reads back equal, through PyYAML's reader
(YAML 1.1) and through this package's exact reader (YAML 1.2 core, exact numbers)."""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import pytest
import yaml
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from uio_ring.spec.yaml_io import _key_identity, dump_yaml, load_yaml_text
from uio_ring.spec.yaml_writer import dump_plain_yaml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

# text that looks like a number, a date, a boolean, null, a document marker or an indicator
TRICKY = ["0", "-2", "+3", "1e5", "1.5", ".5", "1_000", "0x1F", "0o17", "0b101", "017", ".inf", "-.inf", ".nan",
          "yes", "No", "on", "OFF", "y", "n", "true", "False", "null", "~", "", "2001-12-14", "2001-12-14 21:59:43.10",
          "1:30", "<<", "=", "-", "- a", "--- x", "... y", "? k", ": v", "a: b", "a #b", "#c", "[x]", "{y}", "a,b",
          "&anchor", "*alias", "!tag", "|", ">", "'q'", '"q"', " lead", "trail ", "two  spaces", "tab\there",
          "line\nbreak", "\x85", "\u2028", "\u00a0", "\ufeff", "😀", "\U0001d173", "é", "back\\slash",
          "-3*d", "2*d + 1", "1/3", "d^2", "(d - 1)^2", "x_hat", "δ", "Ō_L⁻¹"]

scalars = st.one_of(
    st.text(max_size=12), st.sampled_from(TRICKY), st.integers(), st.booleans(), st.none(),
    st.floats(allow_nan=False),
)
data = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8) | st.sampled_from(TRICKY), inner, max_size=4)),
    max_leaves=30,
)


def _exact(x):
    """What the exact reader gives back for written data: a finite float as the exact
    value of its decimal text (``repr``), never through binary."""
    if isinstance(x, float) and math.isfinite(x):
        return Fraction(repr(x))
    if isinstance(x, list):
        return [_exact(v) for v in x]
    if isinstance(x, dict):
        return {k: _exact(v) for k, v in x.items()}
    return x


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(st.text(max_size=8) | st.sampled_from(TRICKY), data, max_size=5))
def test_any_plain_data_reads_back_equal(d):
    text = dump_plain_yaml(d)
    assert yaml.safe_load(text) == (d or {})
    assume(_keys_distinct(d))  # the exact reader refuses keys naming one thing ('0' and '0.0', ' a' and 'a')
    assert load_yaml_text(text, max_bytes=10**7) == _exact(d)


def _keys_distinct(x) -> bool:
    if isinstance(x, dict):
        ids = [_key_identity(k.strip()) for k in x]
        return len(set(ids)) == len(ids) and all(_keys_distinct(v) for v in x.values())
    return all(_keys_distinct(v) for v in x) if isinstance(x, list) else True


@pytest.mark.parametrize("s", TRICKY)
def test_each_tricky_string_alone_and_in_a_row(s):
    d = {s: s, "row": [s, s], "nested": [[s], {s: [s]}]}
    text = dump_plain_yaml(d)
    assert yaml.safe_load(text) == d
    assert load_yaml_text(text) == d


def test_quoted_only_when_a_reader_could_take_it_for_something_else():
    text = dump_plain_yaml({"row": ["-3*d", "2*d + 1", "1/3", "d", "0", "1e5", "yes", "2001-12-14", ".inf"]})
    assert text == "row: [-3*d, 2*d + 1, 1/3, d, '0', '1e5', 'yes', '2001-12-14', '.inf']\n"


def test_floats_special_values_and_fractions():
    text = dump_plain_yaml({"x": [1e-05, 1.5, float("inf"), float("-inf"), float("nan"), Fraction(-1, 3), 10**30]})
    back = yaml.safe_load(text)["x"]
    assert back[:4] == [1e-05, 1.5, math.inf, -math.inf] and math.isnan(back[4]) and back[5:] == ["-1/3", 10**30]


def test_unwritable_values_are_refused():
    with pytest.raises(TypeError):
        dump_plain_yaml({"x": object()})
    with pytest.raises(TypeError):
        dump_plain_yaml({1: "non-text key"})


@pytest.mark.parametrize("name", ["zheng2015.yaml", "bejarano2007_example1.yaml", "aircraft_normal_form.yaml"])
def test_design_file_text_reads_back_as_its_data(name):
    """A design's YAML is its data (both readers), and a matrix row is one line."""
    from uio_ring.design.methods import design_auto
    from uio_ring.spec import load_spec
    from uio_ring.spec.designs import design_to_data

    spec = load_spec(EXAMPLES / name)
    data = design_to_data(design_auto(spec.system, **spec.design.options).design)
    text = dump_yaml(data)
    assert yaml.safe_load(text) == data
    assert load_yaml_text(text, max_bytes=10**8)["fields"] == data["fields"]
    A = data["fields"]["system"]["$system"]["A"]
    assert f"- [{', '.join(A[0])}]" in text or any(not (s and s[0].isalpha() or s.startswith('-')) for s in A[0])
