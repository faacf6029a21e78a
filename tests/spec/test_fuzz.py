"""Property: whatever text the loader gets, it either loads or raises SpecError."""

from __future__ import annotations

import re
import time
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


# ---------------------------------------------------------------------------------------
# hostile texts (issue 16): long, deeply nested, huge numbers, duplicate keys, bad names.
# Each must load or raise SpecError, within a time budget measured here (generous: the
# limits are checked before the work, so every case takes milliseconds).
# ---------------------------------------------------------------------------------------
BUDGET_S = 20.0

HUGE_NUMBERS = st.sampled_from(
    ["1e99999999", "-1e-99999999", "9" * 5000, "1e400", "1e-400", "1e308", "0." + "0" * 3000 + "1", "1:30",
     "0x1F", "0o17", "1_000", ".nan", "-.inf", "yes", "2001-12-14", "1/0", "'1e99999'", "'(1+d)**4096'"]
)
NASTY_NAMES = st.sampled_from(
    ["../x", "/etc/passwd", ".", "..", "t", "a,b", "'a\\nb'", "error_x", "xhat_x", "''", "'  '", "n" * 300, "'a.b'"]
)
NESTED = st.builds(
    lambda kind, n: {"paren": "'" + "(" * n + "d" + ")" * n + "'", "minus": "'" + "-" * n + "d'",
                     "list": "[" * n + "0" + "]" * n, "pow": "'" + "d**2**" * n + "d'",
                     "sum": "'" + "+".join(["d"] * n) + "'"}[kind],
    st.sampled_from(["paren", "minus", "list", "pow", "sum"]),
    st.integers(1, 20_000),
)
VALUES = st.one_of(HUGE_NUMBERS, NESTED, st.integers(-(10**30), 10**30).map(str))
SLOTS = [
    ("system.A[1][1]", lambda v: TEXTS_BY_NAME["zheng2015"].replace("[-1, d, 0, 0]", f"[-1, {v}, 0, 0]")),
    ("system.h", lambda v: TEXTS_BY_NAME["zheng2015"].replace("h: 0.01", f"h: {v}")),
    ("design.poles", lambda v: TEXTS_BY_NAME["zheng2015"].replace("poles: [-10, -25, -50]", f"poles: [{v}, -25, -50]")),
    ("simulate.t_final", lambda v: TEXTS_BY_NAME["zheng2015"].replace("t_final: 3", f"t_final: {v}")),
    ("simulate.w", lambda v: TEXTS_BY_NAME["zheng2015"].replace('"-10*sin(100*t)"', v if v.startswith("'") else f"'{v}'")),
]
TEXTS_BY_NAME = {p.stem: t for p, t in zip(EXAMPLES, TEXTS, strict=True)}


def _bounded(text: str) -> None:
    start = time.perf_counter()
    _loads_or_spec_error(text)
    elapsed = time.perf_counter() - start
    assert elapsed < BUDGET_S, f"took {elapsed:.1f} s"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(slot=st.sampled_from(SLOTS), value=VALUES)
def test_hostile_values_in_every_slot(slot, value):
    _bounded(slot[1](value))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(name=NASTY_NAMES, where=st.sampled_from(["name: {}\n", "system:\n  states: [{}, b, c, e]\n"]))
def test_hostile_names(name, where):
    text = TEXTS_BY_NAME["zheng2015"]
    if where.startswith("name"):
        text = text.replace("name: zheng2015\n", where.format(name))
    else:
        text = text.replace("  unknown_inputs: [w1, w2]\n", "  unknown_inputs: [w1, w2]\n  states: [" + name + ", b, c, e]\n")
    try:
        spec = load_spec_text(text)
    except SpecError:
        return
    # what loads is safe: one file name, no separators; names fit CSV columns ``x.<name>``
    assert "/" not in spec.name and not spec.name.startswith(".")
    names = list(spec.system.state_names)
    assert len(set(names)) == len(names)
    assert not any(c in n for n in names for c in ".,\"'\n")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(k=st.integers(0, len(TEXTS) - 1), copies=st.integers(1, 3), line=st.integers(0, 200))
def test_duplicated_lines_never_silently_win(k, copies, line):
    """Repeating a ``key: …`` line is always refused: the last one never silently wins."""
    lines = TEXTS[k].splitlines(keepends=True)
    i = line % len(lines)
    text = "".join(lines[: i + 1] + [lines[i]] * copies + lines[i + 1 :])
    is_key = re.match(r"^\s*[A-Za-z_]\w*:(\s|$)", lines[i]) is not None
    try:
        load_spec_text(text)
    except SpecError as exc:
        if is_key:
            assert "appears twice" in str(exc) or "not valid YAML" in str(exc)
        return
    assert not is_key, f"the repeated line {lines[i].strip()!r} was accepted"


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet=st.sampled_from(list("()[]{}-+*/^d0123456789.e: ,'\"\n")), min_size=1000, max_size=20_000))
def test_long_random_texts(text):
    _bounded("system:\n  A: " + text + "\n  B: [[1]]\n  C: [[1]]\n")
    _bounded(text)
