"""``load_design`` does not trust the file: types, shapes, bounded numbers, and the certificate re-run."""

from __future__ import annotations

import copy
import json
import os
import time
from pathlib import Path

import pytest

from uio_ring import DelaySystem, design_zheng_bejarano
from uio_ring.errors import SpecError
from uio_ring.spec import load_design, save_design


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    design = design_zheng_bejarano(DelaySystem("[[0, 1], [-1, -d]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None, h="0.1"),
                                   poles=[-2])
    folder = tmp_path_factory.mktemp("design")
    paths = save_design(design, folder / "small", formats=("json", "yaml"))
    return design, json.loads(paths[0].read_text(encoding="utf-8"))


def _edit(data, field, value):
    data = copy.deepcopy(data)
    data["fields"][field] = value
    return data


EDITS = [
    ("L0 edited", lambda d: _edit(d, "L0", {"$matrix": [["-2", "0"], ["0", "-3"]], "shape": [2, 2]}),
     r"fails its certificate"),
    ("poles edited", lambda d: _edit(d, "poles", {"$tuple": [{"$q": "-3"}]}), r"fails its certificate"),
    ("L0 is the integer 5", lambda d: _edit(d, "L0", 5), r"fields\.L0: int '5' where a matrix is expected"),
    ("L0 wrong shape", lambda d: _edit(d, "L0", {"$matrix": [["-2"]], "shape": [1, 1]}),
     r"do not fit together|fails its certificate"),
    ("rows disagree with shape", lambda d: _edit(d, "L0", {"$matrix": [["-2", "0"]], "shape": [2, 2]}),
     r"fields\.L0: the entries do not form the 2×2 matrix"),
    ("huge shape", lambda d: _edit(d, "L0", {"$matrix": [], "shape": [10**9, 0]}), r"fields\.L0: shape .* not two whole numbers"),
    ("huge exponent", lambda d: _edit(d, "poles", {"$tuple": [{"$q": "1e99999999"}]}), r"fields\.poles\[0\]: .*digits"),
    ("huge power", lambda d: _edit(d, "L0", {"$matrix": [["(1+d)**4096*(1+d)**4096", "0"], ["0", "-2"]], "shape": [2, 2]}),
     r"fields\.L0: .*degree 8192"),
    ("deep parentheses", lambda d: _edit(d, "L0", {"$matrix": [["(" * 5000 + "1" + ")" * 5000, "0"], ["0", "-2"]],
                                                   "shape": [2, 2]}), r"fields\.L0: .*nested deeper"),
    ("r is text", lambda d: _edit(d, "r", "two"), r"fields\.r: str 'two' where int is expected"),
    ("r is a float", lambda d: _edit(d, "r", 1.5), r"fields\.r: float '1\.5' where int is expected"),
    ("a pole is a float", lambda d: _edit(d, "poles", {"$tuple": [-2.0]}), r"fields\.poles\[0\]: float '-2\.0' where Fraction"),
    ("poles is a number", lambda d: _edit(d, "poles", {"$q": "-2"}), r"fields\.poles: .*where tuple"),
    ("unknown record", lambda d: _edit(d, "system", {"$dataclass": "os.system", "fields": {}}), r"unknown record type"),
    ("a field missing", lambda d: {**d, "fields": {k: v for k, v in d["fields"].items() if k != "H"}}, r"has no field 'H'"),
]


@pytest.mark.parametrize("case,edit,pattern", EDITS, ids=[e[0] for e in EDITS])
def test_edited_design_files_are_refused(saved, tmp_path, case, edit, pattern):
    _, data = saved
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(edit(data)), encoding="utf-8")
    start = time.perf_counter()
    with pytest.raises(SpecError, match=pattern) as info:
        load_design(path)
    assert time.perf_counter() - start < 10
    assert "\n" not in str(info.value) and len(str(info.value)) < 600


def test_verify_false_loads_an_edited_design_and_its_certificate_fails(saved, tmp_path):
    _, data = saved
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(EDITS[0][1](data)), encoding="utf-8")
    design = load_design(path, verify=False)
    assert not design.certificate().ok


def test_untouched_files_load_equal(saved, tmp_path):
    design, data = saved
    path = tmp_path / "same.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    assert load_design(path) == design


RAW = [
    ('{"uio_ring_design": 1, "method": "zheng-bejarano", "fields": {"r": 1.5}}', r"has no field|float"),
    ('{"uio_ring_design": 1, "x": ' + "9" * 5000 + "}", r"integer of 5000 digits"),
    ('{"a": NaN}', r"not a uio_ring design file"),
    ("[" * 100_000 + "]" * 100_000, r"nested too deeply|not a uio_ring design"),
    ("{not json", r"not valid JSON"),
    ('{"uio_ring_design": 1, "method": "nope"}', r"unknown design method"),
    ('{"uio_ring_design": 1, "method": "zheng-bejarano", "fields": []}', r"'fields' is not a mapping"),
]


@pytest.mark.parametrize("text,pattern", RAW, ids=[p for _, p in RAW])
def test_malformed_design_files_raise_spec_error(tmp_path, text, pattern):
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SpecError, match=pattern):
        load_design(path)


def test_design_files_are_read_only_from_regular_files(tmp_path):
    if Path("/dev/zero").exists():
        with pytest.raises(SpecError, match="not a regular file"):
            load_design("/dev/zero")
    if hasattr(os, "mkfifo"):
        fifo = tmp_path / "fifo.json"
        os.mkfifo(fifo)
        with pytest.raises(SpecError, match="not a regular file"):
            load_design(fifo)  # returns at once: opened non-blocking, refused before reading


def test_large_exact_numbers_round_trip(tmp_path):
    """Designs multiply the spec's numbers: files hold numbers beyond Python's 4 300-digit text limit."""
    design = design_zheng_bejarano(DelaySystem("[[0, 1], [-1, -d]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None, h="0.1"),
                                   poles=["-1e-999"])
    paths = save_design(design, tmp_path / "big", formats=("json", "yaml"))
    assert load_design(paths[0]) == design == load_design(paths[1])
