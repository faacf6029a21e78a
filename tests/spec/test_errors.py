"""Bad spec input: every error names the YAML path and what would fix it."""

from __future__ import annotations

import pytest

from uio_ring.errors import SpecError
from uio_ring.spec import load_spec, load_spec_text

BASE_SYSTEM = "  A: [[0, 1], [-1, -1]]\n  B: [[0], [1]]\n  C: [[1, 0], [0, 1]]\n  h: 0.1\n"


def spec_with(system: str = BASE_SYSTEM, rest: str = "") -> str:
    return "system:\n" + system + rest


CASES = [
    # (yaml text, regex on the message)
    (spec_with("  A: [[0, 1], [-1, -1]]\n  B: [[0], [1]]\n  C: [[1, 0], ['1+*d', 0]]\n  h: 1\n"),
     r"^system\.C\[1\]\[0\]: cannot parse '1\+\*d' at column 3"),
    (spec_with("  A: [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]\n"
               "  B: [[0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]]\n"
               "  C: [[1, 0, 0, 0]]\n  D: [[0, 0]]\n"),
     r"^system\.B: B is 4×3 but A is 4×4 and w has 2 components"),
    (spec_with("  A: [[0, 1], [-1, -1]]\n  B: [[0], [1]]\n  C: [[1, 0, 0]]\n"), r"^system\.C: C is 1×3 but A is 2×2"),
    (spec_with("  A: [[0, 1]]\n  B: [[0]]\n  C: [[1, 0]]\n"), r"^system\.A: A is 1×2; it must be square"),
    (spec_with(BASE_SYSTEM.replace("h: 0.1", "h: 0")), r"^system\.h: .*must be positive"),
    (spec_with(BASE_SYSTEM.replace("h: 0.1", "h: -1")), r"^system\.h: .*must be positive"),
    (spec_with(BASE_SYSTEM, "simulate:\n  t_final: 1\n  dt: 0.03\n"), r"^simulate\.dt: h/dt = 10/3 is not a whole number.*dt = h/N"),
    (spec_with(BASE_SYSTEM.replace("  h: 0.1\n", "  hh: 0.1\n")), r"^system\.hh: unknown key 'hh'; did you mean 'h'\?"),
    ("sytem:\n" + BASE_SYSTEM, r"^sytem: unknown key 'sytem'; did you mean 'system'\?"),
    (spec_with(BASE_SYSTEM, "design:\n  method: zheng-bejarno\n"), r"^design\.method: unknown key|^design\.method: .*did you mean 'zheng-bejarano'"),
    (spec_with("  A: {0: [[0]], 0.5: [[1]]}\n  B: [[1]]\n  C: [[1]]\n  h: 1\n"), r"^system\.A: delay multiple 0\.5 is not a whole number"),
    (spec_with("  A: [[d**100]]\n  B: [[1]]\n  C: [[1]]\n  h: 1\n"), r"^system\.A\[0\]\[0\]: 'd\*\*100', column 4: the power has degree 100, above the limit 16"),
    (spec_with("  A: [[d]]\n  B: [[1]]\n  C: [[1]]\n"), r"^system\.h: the matrices contain d .* add h"),
    (spec_with("  A: [[x]]\n  B: [[1]]\n  C: [[1]]\n  h: 1\n"), r"^system\.A\[0\]\[0\]: .*unknown symbol 'x'"),
    (spec_with("  A: [[sqrt(2)]]\n  B: [[1]]\n  C: [[1]]\n  h: 1\n"), r"^system\.A\[0\]\[0\]: .*'sqrt' is not rational"),
    (spec_with("  A: [[1, 2], [3]]\n  B: [[1], [1]]\n  C: [[1, 1]]\n  h: 1\n"), r"^system\.A\[1\]: row 1 has 1 entries but row 0 has 2"),
    (spec_with(BASE_SYSTEM, "simulate:\n  t_final: 1\n  dt: 0.01\n  w: ['sin(t', '0']\n"), r"^simulate\.w: 2 expression\(s\) given for 1 unknown inputs"),
    (spec_with(BASE_SYSTEM, "simulate:\n  t_final: 1\n  dt: 0.01\n  w: ['sin(t']\n"), r"^simulate\.w\[0\]: cannot parse 'sin\(t' at column 6"),
    (spec_with(BASE_SYSTEM, "simulate:\n  t_final: 1\n  dt: 0.01\n  w: ['__import__(1)']\n"), r"^simulate\.w\[0\]: .*unknown name '__import__'"),
    (spec_with(BASE_SYSTEM, "simulate:\n  t_final: 1e9\n  dt: 0.01\n"), r"^simulate: .*steps exceed the limit"),
    ("", r"the file is empty"),
    ("- just\n- a list\n", r"the top level is a list; a spec is a mapping with a 'system' section"),
    ("system: [1, 2\n", r"not valid YAML at line"),
    ("system:\n  A: [[1]]\n", r"'B' is a required property"),
]


@pytest.mark.parametrize("text,pattern", CASES)
def test_bad_spec_messages(text, pattern):
    with pytest.raises(SpecError, match=pattern):
        load_spec_text(text)


def test_yaml_bomb_is_refused_quickly():
    bomb = 'a: &a ["x","x","x","x","x","x","x","x","x"]\n'
    prev = "a"
    for name in "bcdefghijklmnopqrstuvwxyz":
        bomb += f"{name}: &{name} [*{prev},*{prev},*{prev},*{prev},*{prev},*{prev},*{prev},*{prev},*{prev}]\n"
        prev = name
    with pytest.raises(SpecError, match="aliases"):
        load_spec_text(bomb)


def test_huge_file_is_refused():
    with pytest.raises(SpecError, match="larger than"):
        load_spec_text("system:\n  A: [[" + ", ".join(["1"] * 400_000) + "]]\n")


def test_huge_size_is_refused_with_the_limit():
    n = 100
    row = "[" + ", ".join(["0"] * n) + "]"
    text = "system:\n  A: [" + ", ".join([row] * n) + "]\n  B: [[1]]\n  C: [[1]]\n"
    with pytest.raises(SpecError, match=r"system\.A: 100 rows exceed the limit of 64"):
        load_spec_text(text)


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(SpecError, match="no such file"):
        load_spec(tmp_path / "nope.yaml")
    with pytest.raises(SpecError, match="is a directory"):
        load_spec(tmp_path)


def test_binary_file_is_not_yaml(tmp_path):
    p = tmp_path / "x.yaml"
    p.write_bytes(b"\xff\xfe\x00\x01binary")
    with pytest.raises(SpecError, match="not UTF-8"):
        load_spec(p)
