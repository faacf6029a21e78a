"""Property: whatever text the loader gets, it either loads or raises SpecError."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uio_ring.errors import SpecError
from uio_ring.spec import load_spec_text

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples").glob("*.yaml"))
TEXTS = [p.read_text(encoding="utf-8") for p in EXAMPLES]

YAMLISH = st.sampled_from(list(":[]{},-*&!|>'\"#\n ") + ["d", "δ", "1/0", "1e999", "0.1", "**", "A:", "system:", "h:", ".inf", "~", "\t"])


def _loads_or_spec_error(text: str) -> None:
    try:
        load_spec_text(text)
    except SpecError:
        pass


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(max_size=200))
def test_random_text(text):
    _loads_or_spec_error(text)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    k=st.integers(0, len(TEXTS) - 1),
    edits=st.lists(st.tuples(st.integers(0, 10_000), st.integers(0, 3), YAMLISH), min_size=1, max_size=6),
)
def test_mutated_examples(k, edits):
    text = TEXTS[k]
    for pos, cut, ins in edits:
        pos %= len(text) + 1
        text = text[:pos] + ins + text[pos + cut :]
    _loads_or_spec_error(text)
