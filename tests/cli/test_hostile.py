"""Hostile and careless input to the command line (issue 16), one table per class.

Every refused case asserts: exit code 2, exactly one line on stderr, that the
line names the YAML path (or the option) at fault, no traceback, and that no
file appeared anywhere outside the output folder (for refused runs: no file
at all).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uio_ring.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

SYSTEM = "  A: [[0, 1], [-1, -d]]\n  B: [[0], [1]]\n  C: [[1, 0], [0, 1]]\n  h: 0.1\n"
DESIGN = "design:\n  poles: [-2]\n"
SIMULATE = "simulate:\n  t_final: 0.5\n  dt: 0.01\n  w: ['sin(t)']\n  phi: [1, 0]\n"


def spec(system: str = SYSTEM, design: str = DESIGN, simulate: str = SIMULATE, top: str = "name: small\n") -> str:
    return top + "system:\n" + system + design + simulate


def with_sim(**fields: str) -> str:
    """The spec with simulate fields added or replaced (values are YAML text)."""
    lines = {"t_final": "0.5", "dt": "0.01", "w": "['sin(t)']", "phi": "[1, 0]"}
    lines.update(fields)
    return spec(simulate="simulate:\n" + "".join(f"  {k}: {v}\n" for k, v in lines.items()))


def files_under(root: Path) -> set[Path]:
    return {p for p in root.rglob("*") if p.is_file()}


@pytest.fixture
def work(tmp_path, monkeypatch):
    """A working folder (the current directory) with the spec; output goes to ./out unless a case says otherwise."""
    folder = tmp_path / "work"
    folder.mkdir()
    monkeypatch.chdir(folder)
    return folder


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_refused(code: int, err: str, where: str) -> None:
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2, err
    assert len(lines) == 1, err
    assert lines[0].startswith("uio-ring: error: "), err
    assert where in lines[0], (where, lines[0])
    assert "Traceback" not in err


def refuse(work: Path, capsys, text: str, where: str, command: str = "design", extra: tuple[str, ...] = ()) -> str:
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    before = files_under(work.parent)
    start = time.perf_counter()
    code, _, err = run(capsys, command, "spec.yaml", "--out", "out", *extra,
                       *(["--no-progress", "--no-plot"] if command == "simulate" else []))
    assert time.perf_counter() - start < 30  # bounded work: refused long before any hang
    assert_refused(code, err, where)
    assert files_under(work.parent) == before  # nothing written anywhere
    return err


# ---------------------------------------------------------------------------------------
# 1. work is bounded before it is done
# ---------------------------------------------------------------------------------------
POWER_CHAIN = "(1+d)**4096*" * 15 + "(1+d)**4096"
BOUNDED = [
    ("design", spec(system=SYSTEM.replace("[-1, -d]", "[-1, 1e99999999]")), "system.A[1][1]"),
    ("design", spec(system=SYSTEM.replace("[-1, -d]", f"[-1, '{POWER_CHAIN}']")), "system.A[1][1]"),
    ("design", spec(system=SYSTEM.replace("[[0, 1], [-1, -d]]", f"'[[0, 1], [-1, {POWER_CHAIN}]]'")), "system.A"),
    ("design", spec(system=SYSTEM.replace("[-1, -d]", "[-1, 'd**17']")), "system.A[1][1]"),
    ("design", spec(system=SYSTEM.replace("[-1, -d]", "[-1, '(10**1000)**1000']")), "system.A[1][1]"),
    ("design", spec(system=SYSTEM.replace("h: 0.1", "h: 1e-5000")), "system.h"),
    ("design", spec(system=SYSTEM.replace("h: 0.1", "h: " + "7" * 5000)), "system.h"),
    ("design", spec(system=SYSTEM.replace("h: 0.1", "h: '1e99999999'")), "system.h"),
    ("design", spec(design="design:\n  poles: [1e5000]\n"), "design.poles[0]"),
    ("design", spec(design="design:\n  poles: ['-10**5000']\n"), "design.poles[0]"),
    ("design", spec(system=SYSTEM.replace("[-1, -d]", "[-1, '" + "(" * 5000 + "d" + ")" * 5000 + "']")), "system.A[1][1]"),
    ("design", spec(system=SYSTEM.replace("[[0, 1], [-1, -d]]", "{0: [[0, 1], [-1, 0]], 99999999999: [[0, 0], [0, 1]]}")), "system.A"),
    ("design", spec(system="  A: " + "[" * 40 + "0" + "]" * 40 + "\n  B: [[1]]\n  C: [[1]]\n"), "system.A"),
    ("simulate", with_sim(t_final="1e5000"), "simulate.t_final"),
    ("simulate", with_sim(dt="1e-400"), "simulate.dt"),
    ("simulate", with_sim(x_hat0="[1e400, 0]"), "simulate.x_hat0[0]"),
    ("simulate", with_sim(noise="{bound: 1e400}"), "simulate.noise.bound"),
    ("simulate", with_sim(noise="{bound: 1e308}"), "simulate.noise.bound"),
    ("simulate", with_sim(noise="{bound: 1, seed: -1}"), "simulate.noise.seed"),
    ("simulate", with_sim(noise="{bound: 1, seed: 1e99999999}"), "simulate.noise.seed"),
    ("simulate", with_sim(w="['" + "t**" * 600 + "t']"), "simulate.w[0]"),
    ("simulate", with_sim(w="['" + "(" * 900 + "t" + ")" * 900 + "']"), "simulate.w[0]"),
    ("simulate", with_sim(w="['1e400*t']"), "simulate.w[0]"),
    ("simulate", with_sim(settle="1e99999999"), "simulate.settle"),
    # runs kept in memory (NPZ output, a nonlinearity) are bounded at 5e7 values; CSV runs are streamed
    ("simulate", with_sim(t_final="200000") + "output:\n  formats: [npz]\n",
     "simulate: 20000000 steps × 11 recorded signals"),
    ("simulate", spec(system="  A: [[0, 1], [-1, 0]]\n  B: [[0], [1]]\n  C: [[1, 0], [0, 1]]\n",
                      simulate="simulate:\n  t_final: 200000\n  dt: 0.01\n  nonlinearity: ['0', '-x1**3']\n"),
     "simulate: 20000000 steps × 11 recorded signals"),
    ("simulate", with_sim(t_final="1e9"), "simulate: t_final/dt"),
]


@pytest.mark.parametrize("command,text,where", BOUNDED, ids=[f"{c}:{w}:{i}" for i, (c, _, w) in enumerate(BOUNDED)])
def test_bounded_work_is_refused_with_the_path(work, capsys, command, text, where):
    refuse(work, capsys, text, where, command)


def test_long_signs_and_sums_finish(work, capsys):
    text = with_sim(w="['" + "-" * 1500 + "sin(t)']", phi="['" + "+".join(["t"] * 400) + "', 0]")
    text = text.replace("[-1, -d]", "[-1, '" + "-" * 99_999 + "d']")
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress", "--no-plot")
    assert code == 0, err
    assert "simulated 0.5 s" in out


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/null", "/dev/urandom"])
def test_devices_are_refused_without_reading(capsys, path):
    if not Path(path).exists():
        pytest.skip(f"{path} does not exist here")
    code, _, err = run(capsys, "check", path)
    assert_refused(code, err, path)
    assert "not a regular file" in err


def test_a_fifo_without_writer_does_not_block(tmp_path):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs on this platform")
    fifo = tmp_path / "spec.yaml"
    os.mkfifo(fifo)
    proc = subprocess.run([sys.executable, "-m", "uio_ring.cli", "check", str(fifo)], capture_output=True,
                          text=True, timeout=60, check=False)
    assert_refused(proc.returncode, proc.stderr, str(fifo))


def test_ctrl_c_exits_130_without_traceback_or_files(tmp_path):
    """SIGINT during a long run: exit 130, one line, no traceback, no file (finished or partial)."""
    spec_path = tmp_path / "long.yaml"
    # a differentiator observer steps in the Python loop (≈ 10⁵ steps/s): 2·10⁶ steps take far longer than
    # the 4 s before the interrupt, however fast the machine is
    spec_path.write_text(
        "name: long\nsystem:\n  A: [[0, 1], [0, 0]]\n  B: [[0], [1]]\n  C: [[1, 0]]\n"
        "design:\n  method: normal-form\n  input_bounds: [1]\n"
        "simulate:\n  t_final: 2000\n  dt: 0.001\n  w: ['sin(t)']\n  phi: [1, 0]\n", encoding="utf-8")
    out = tmp_path / "out"
    # the Python step loop: the compiled one (numba, when installed) runs 2·10⁶ steps in about 3 s
    env = {**os.environ, "UIO_RING_KERNEL": "python"}
    proc = subprocess.Popen([sys.executable, "-m", "uio_ring.cli", "simulate", str(spec_path), "--out", str(out),
                             "--no-progress"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    time.sleep(4)  # well inside the design or the simulation
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if proc.returncode == 0:
        pytest.fail("the run finished before the interrupt; make it longer")
    assert proc.returncode == 130, err
    assert err.strip().splitlines() == ["uio-ring: interrupted"]
    assert not out.exists() or not any(out.iterdir())


# ---------------------------------------------------------------------------------------
# 2. files: nothing outside the output folder, nothing overwritten, nothing half-written
# ---------------------------------------------------------------------------------------
FILES = [
    (spec(top="name: ../x\n"), "name", ()),
    (spec(top="name: /tmp/evil\n"), "name", ()),
    (spec(top="name: '.'\n"), "name", ()),
    (spec(top="name: '..'\n"), "name", ()),
    (spec(top="name: .hidden\n"), "name", ()),
    (spec(top="name: \"a\\u0001b\"\n"), "name", ()),
    (spec(top="name: " + "n" * 300 + "\n"), "name", ()),
    (spec(top="name: small\noutput:\n  directory: /tmp/abs\n"), "output.directory", ("--out",)),
    (spec(top="name: small\noutput:\n  directory: ../up\n"), "output.directory", ("--out",)),
    (spec(top="name: small\noutput:\n  directory: a/../../up\n"), "output.directory", ("--out",)),
]


@pytest.mark.parametrize("text,where,drop", FILES, ids=[f"{w}:{i}" for i, (_, w, _) in enumerate(FILES)])
def test_names_and_folders_stay_inside(work, capsys, text, where, drop):
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    before = files_under(work.parent.parent)
    argv = ["design", "spec.yaml"] + ([] if "--out" in drop else ["--out", "out"])
    code, _, err = run(capsys, *argv)
    assert_refused(code, err, where)
    assert files_under(work.parent.parent) == before


OUT_OPTIONS = [
    (lambda w: str(w / "spec.yaml"), "--out", "exists and is not a folder"),
    (lambda w: str(w / "spec.yaml" / "sub"), "--out", "is a file"),
    (lambda w: "out\x00put", "--out", "NUL"),
    (lambda w: "o" * 300, "--out", "too long"),
    (lambda w: "", "--out", "empty folder name"),
]


@pytest.mark.parametrize("out,where,reason", OUT_OPTIONS, ids=[r for _, _, r in OUT_OPTIONS])
def test_bad_out_is_refused_with_the_reason(work, capsys, out, where, reason):
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    before = files_under(work.parent)
    code, _, err = run(capsys, "design", "spec.yaml", "--out", out(work))
    assert_refused(code, err, where)
    assert reason in err
    assert files_under(work.parent) == before


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root ignores permissions")
def test_unwritable_out_is_refused(work, capsys):
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    locked = work / "locked"
    locked.mkdir(mode=0o500)
    code, _, err = run(capsys, "design", "spec.yaml", "--out", str(locked / "sub"))
    assert_refused(code, err, "--out")
    assert "permission denied" in err


def test_existing_outputs_are_not_overwritten_without_force(work, capsys):
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    assert run(capsys, "design", "spec.yaml", "--out", "out", "--latex", "d.tex")[0] == 0
    written = {p: p.read_bytes() for p in files_under(work)}
    (work / "out" / "small.json").write_text("mine")
    code, _, err = run(capsys, "design", "spec.yaml", "--out", "out")
    assert_refused(code, err, "--out")
    assert "already exist" in err and "--force" in err
    assert (work / "out" / "small.json").read_text() == "mine"
    (work / "out" / "small.json").unlink()
    (work / "out" / "small.yaml").unlink()
    (work / "d.tex").write_text("mine")
    code, _, err = run(capsys, "design", "spec.yaml", "--out", "out", "--latex", "d.tex")
    assert_refused(code, err, "--latex")
    assert "other content" in err and (work / "d.tex").read_text() == "mine"
    assert not (work / "out" / "small.json").exists()  # refused before anything is written
    code, _, err = run(capsys, "design", "spec.yaml", "--out", "out", "--latex", "d.tex", "--force")
    assert code == 0, err
    assert {p: p.read_bytes() for p in files_under(work)} == written


def test_design_files_with_the_same_bytes_are_left_as_they_are(work, capsys):
    """design, then simulate (or design again) in one folder: the design's files are the
    run's own bytes, so nothing is replaced and the run goes on; the CSV and PNG of an earlier
    simulation are still refused before any work."""
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    assert run(capsys, "design", "spec.yaml", "--out", "out", "--latex", "d.tex")[0] == 0
    design_files = ["out/small.json", "out/small.yaml", "d.tex"]
    before = {name: ((work / name).read_bytes(), (work / name).stat().st_mtime_ns) for name in design_files}
    code, out, err = run(capsys, "design", "spec.yaml", "--out", "out", "--latex", "d.tex")
    assert code == 0, err
    assert "wrote" not in out and "unchanged" in out and "small.json" in out
    code, out, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress")
    assert code == 0, err
    assert "wrote out/small.csv, out/small.png" in out.replace("\\", "/")
    assert {name: ((work / name).read_bytes(), (work / name).stat().st_mtime_ns) for name in design_files} == before
    assert not [p for p in (work / "out").iterdir() if p.name.startswith(".")]  # no temporary file left
    code, _, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress")
    assert_refused(code, err, "--out")
    assert "small.csv" in err and "already exist" in err


@pytest.mark.parametrize("kind", ["other bytes", "symlink", "fifo"])
def test_a_design_file_that_would_change_refuses_the_simulation(work, capsys, kind):
    """With other bytes (or not a regular file) at a design file's path, simulate is refused
    once the design is known: before simulating, with nothing written and nothing read from a FIFO."""
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    assert run(capsys, "design", "spec.yaml", "--out", "out")[0] == 0
    target = work / "out" / "small.json"
    if kind == "other bytes":
        target.write_bytes(target.read_bytes().replace(b"}", b"} ", 1))
    elif kind == "symlink":  # a link to the very same bytes is still not this run's file
        (work / "copy.json").write_bytes(target.read_bytes())
        target.unlink()
        target.symlink_to(work / "copy.json")
    else:
        if not hasattr(os, "mkfifo"):
            pytest.skip("no FIFOs on this platform")
        target.unlink()
        os.mkfifo(target)
    before = files_under(work)
    code, _, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress")
    assert_refused(code, err, "--out")
    assert "small.json" in err and ("other content" in err) == (kind == "other bytes")
    assert files_under(work) == before  # no CSV, no PNG, no temporary file


def test_latex_naming_a_folder_is_refused(work, capsys):
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    code, _, err = run(capsys, "design", "spec.yaml", "--out", "out", "--latex", str(work))
    assert_refused(code, err, "--latex")
    assert not (work / "out").exists()


def test_failed_certificate_writes_nothing(work, capsys):
    (work / "spec.yaml").write_text(spec(design="design:\n  poles: [5]\n"), encoding="utf-8")
    code, out, err = run(capsys, "design", "spec.yaml", "--out", "out")
    assert code == 1
    assert "certificate FAILED" in out and "no design files written" in err
    assert not (work / "out").exists()
    code, out, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress")
    assert code == 1 and not (work / "out").exists()


def test_no_temporary_files_remain_after_success(work, capsys):
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    assert run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress")[0] == 0
    names = sorted(p.name for p in (work / "out").iterdir())
    assert names == ["small.csv", "small.json", "small.png"]


# ---------------------------------------------------------------------------------------
# 3. data are never silently wrong
# ---------------------------------------------------------------------------------------
DATA = [
    (spec(system=SYSTEM + "  A: [[1, 0], [0, 1]]\n"), "system.A", "appears twice"),
    (spec(system=SYSTEM.replace("[[0, 1], [-1, -d]]", "{0: [[0, 1], [-1, 0]], '0': [[0, 0], [0, 1]]}")),
     "system.A", "appears twice"),
    (spec(system=SYSTEM.replace("[[0, 1], [-1, -d]]", "{0: [[0, 1], [-1, 0]], 0.0: [[0, 0], [0, 1]]}")),
     "system.A", "(0, '0' and 0.0 are the same key)"),
    (spec(design="design:\n  poles: [-2]\n  poles: [-3]\n"), "design.poles", "appears twice"),
    (spec(system=SYSTEM.replace("h: 0.1", "h: 1:30")), "system.h", "'1:30'"),
    (spec(system=SYSTEM.replace("[-1, -d]", "[-1, 0x10]")), "system.A[1][1]", "'0x10'"),
    (spec(system=SYSTEM.replace("[-1, -d]", "[-1, 0o17]")), "system.A[1][1]", "'0o17'"),
    (spec(system=SYSTEM.replace("[-1, -d]", "[-1, !!int 1:30]")), "system.A[1][1]", "not a decimal integer"),
    (spec(system=SYSTEM + "  states: [p, p]\n"), "system", "repeated names"),
    (spec(system=SYSTEM + "  states: ['a,b', v]\n"), "system.states[0]", "','"),
    (spec(system=SYSTEM + "  states: [\"a\\nb\", v]\n"), "system.states[0]", "'\\n'"),
    (spec(system=SYSTEM + "  states: ['p\"', v]\n"), "system.states[0]", "contains '\"'"),
    (spec(system=SYSTEM + "  states: [" + "s" * 65 + ", v]\n"), "system.states[0]", "longer than 64"),
    (spec(system=SYSTEM + "  states: [yes, no]\n"), "system.states", None),
    (spec(system=SYSTEM + "  states: [1, 2]\n"), "system.states[0]", "quote it"),
]


@pytest.mark.parametrize("text,where,reason", DATA, ids=[f"{w}:{i}" for i, (_, w, _) in enumerate(DATA)])
def test_ambiguous_data_is_refused(work, capsys, text, where, reason):
    if reason is None:  # yes/no are text under YAML 1.2's rule: valid names, the spec loads
        (work / "spec.yaml").write_text(text, encoding="utf-8")
        code, out, _ = run(capsys, "check", "spec.yaml")
        assert code == 0
        return
    err = refuse(work, capsys, text, where)
    assert reason in err


NON_FINITE = [
    {"w": "['1e308']", "t_final": "5"},  # the plant overflows after 1.4 s: NaN estimates
    {"w": "['1e308*(1 + 100*t)']"},  # the input itself overflows
    {"w": "['1e300*exp(1000*t)']"},
    {"w": "['1/(t - t)']"},  # 1/0 at every step
]


@pytest.mark.parametrize("fields", NON_FINITE, ids=lambda f: ",".join(f.values()))
def test_non_finite_simulation_is_an_error(work, capsys, fields):
    err = refuse(work, capsys, with_sim(**fields), "simulate", "simulate")
    assert "not finite" in err


STIFF_PLANT = "  A: [[-1000000, 0], [1, -1]]\n  B: [[0], [1]]\n  C: [[1, 0], [0, 1]]\n"
UNTRUSTWORTHY = [  # results the grid cannot resolve: a wrong number must not be a success
    spec(system=STIFF_PLANT, design="design:\n  poles: [-1]\n"),  # issue 16: error 4 934 after one step
    spec(system=STIFF_PLANT + "  h: 0.1\n", design="design:\n  poles: [-1]\n"),
    spec(system=STIFF_PLANT.replace("[1, -1]", "[d, -1]") + "  h: 0.1\n", design="design:\n  poles: [-1]\n"),
    spec(system=STIFF_PLANT.replace("-1000000", "-100000"), design="design:\n  poles: [-3]\n"),
]


@pytest.mark.parametrize("text", UNTRUSTWORTHY, ids=["delay-free", "with-h", "delayed", "1e5"])
def test_untrustworthy_simulation_is_an_error(work, capsys, text):
    err = refuse(work, capsys, text, "simulate.dt", "simulate")
    assert "not resolved by dt = 0.01" in err and "reduce dt" in err


def test_stiff_observer_is_accurate_and_succeeds(work, capsys):
    """Observer poles (−10⁶, −25, −50) on paper 001's example: the error 8.4 after 0.2 s is the
    observer's true peaking transient (tests/sim/test_accuracy.py shows it independently)."""
    text = (EXAMPLES / "zheng2015.yaml").read_text(encoding="utf-8")
    text = text.replace("poles: [-10, -25, -50]", "poles: [-1000000, -25, -50]")
    text = text.replace("t_final: 3", "t_final: 0.2").replace("settle: 2", "settle: 0.1")
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress", "--no-plot")
    assert code == 0 and err == "", err
    assert "final error 8.4," in out


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.yaml") if "fails" not in p.name))
def test_examples_pass_the_accuracy_check(name):
    import warnings

    from uio_ring.cli.spec_commands import _design, _simulate
    from uio_ring.sim import AccuracyWarning
    from uio_ring.spec import load_spec

    spec = load_spec(EXAMPLES / name)
    design = _design(spec)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        result = _simulate(design, spec, progress=False)
    assert result.success and result.accuracy.ok, result.message


def test_duplicate_powers_from_python_data_are_refused():
    from uio_ring.errors import SpecError
    from uio_ring.spec import spec_from_dict

    data = {"system": {"A": {0: [[1]], "0": [[2]]}, "B": [[1]], "C": [[1]]}}
    with pytest.raises(SpecError, match=r"^system\.A: the keys 0 and '0' both name the coefficient of d\^0"):
        spec_from_dict(data)


def test_csv_header_is_escaped_and_unique(work, capsys):
    """Columns are ``kind.name``: a state called ``t``, an output sharing a state's name and an output
    called ``error_p`` cannot replace another column; spaces and brackets survive the csv round trip."""
    text = spec(system=SYSTEM + "  states: [t, 'v [m/s]']\n  outputs: ['v [m/s]', error_t]\n")
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    assert run(capsys, "simulate", "spec.yaml", "--out", "out", "--no-progress", "--no-plot")[0] == 0
    import csv

    with open(work / "out" / "small.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[:5] == ["t", "x.t", "x.v [m/s]", "y.v [m/s]", "y.error_t"]
    assert "x_hat.t" in header and "error.v [m/s]" in header
    assert len(set(header)) == len(header) and all(len(r) == len(header) for r in rows)
    assert [float(v) for v in rows[1][:1]] == [0.0]


# ---------------------------------------------------------------------------------------
# random specs inside the limits finish, with exit 0 or 1, within a measured budget
# ---------------------------------------------------------------------------------------
ENTRY = st.sampled_from(["0", "1", "-1", "2", "d", "-d", "1/2", "d + 1", "0.5*d**2", "-3"])


@st.composite
def small_specs(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.integers(1, 2))
    p = draw(st.integers(1, 3))

    def mat(r, c):
        return "[" + ", ".join("[" + ", ".join(draw(ENTRY) for _ in range(c)) + "]" for _ in range(r)) + "]"

    system = f"  A: {mat(n, n)}\n  B: {mat(n, m)}\n  C: {mat(p, n)}\n  h: 0.1\n"
    w = "[" + ", ".join(["'sin(t)'"] * m) + "]"
    sim = f"simulate:\n  t_final: 0.3\n  dt: 0.05\n  w: {w}\n"
    return spec(system=system, design="", simulate=sim)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(text=small_specs(), command=st.sampled_from(["check", "design", "simulate"]))
def test_random_specs_inside_the_limits_finish(tmp_path, capsys, text, command):
    # a fresh folder per call: hypothesis may replay the same example within one test run
    folder = Path(tempfile.mkdtemp(prefix=f"r{command}", dir=tmp_path))
    (folder / "spec.yaml").write_text(text, encoding="utf-8")
    argv = [command, str(folder / "spec.yaml")]
    if command != "check":
        argv += ["--out", str(folder / "out"), "--force"]
    if command == "simulate":
        argv += ["--no-progress", "--no-plot"]
    start = time.perf_counter()
    code = main(argv)
    elapsed = time.perf_counter() - start
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert code in (0, 1, 2), err
    if code == 2:  # only the simulation may refuse (non-finite results of an unstable random plant)
        assert command == "simulate" and err.startswith("uio-ring: error: simulate"), err
    assert elapsed < 120, f"{command} took {elapsed:.1f} s"
    if code != 0:
        assert not (folder / "out").exists()


CALCULATOR = [
    ("[[(1+d)**4096, 1], [d**4095, 1]]", "degree 4096, above the limit 16"),
    ("[[d**17]]", "degree 17, above the limit 16"),
    ("[[" + ", ".join(["1"] * 17) + "]]", "at most 16×16"),
    ("[[1e99999999]]", "more than 1000 digits"),
    ("[[" + "(" * 5000 + "d" + ")" * 5000 + "]]", "nested deeper than 100"),
    ("[[d, 1], [2]]", "row 1 has 1 entries"),
]


@pytest.mark.parametrize("text,reason", CALCULATOR, ids=[r for _, r in CALCULATOR])
def test_calculator_is_bounded(capsys, text, reason):
    for command in ("hermite", "smith"):
        code, _, err = run(capsys, command, text)
        assert_refused(code, err, "")
        assert reason in err


@pytest.mark.parametrize("out", ["/proc/uio-ring-test", "/proc/self/uio-ring-test/sub"])
def test_out_on_a_virtual_file_system_is_refused_before_any_work(work, capsys, out):
    """Unwritable even for root: refused by a probe before the design runs, nothing left behind."""
    if not Path("/proc/self").exists():
        pytest.skip("no /proc here")
    (work / "spec.yaml").write_text(spec(), encoding="utf-8")
    code, stdout, err = run(capsys, "design", "spec.yaml", "--out", out)
    assert_refused(code, err, "--out")
    assert "cannot write into" in err
    assert "certificate" not in stdout  # refused before the design


def test_folders_made_for_a_run_that_writes_nothing_are_removed(work, capsys):
    (work / "spec.yaml").write_text(spec(design="design:\n  poles: [5]\n"), encoding="utf-8")
    code, _, _ = run(capsys, "design", "spec.yaml", "--out", "a/b/c", "--latex", "x/y/d.tex")
    assert code == 1
    assert not (work / "a").exists() and not (work / "x").exists()


EXAMPLES_DIR = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("poles", ["[-1e-6, -25, -50]", "[-1e-300, -25, -50]", "[-1e999, -25, -50]"])
def test_extreme_poles_design_exactly_and_skip_the_float_figures(work, capsys, poles):
    """Exact designs whose float image overflows, or whose figures would need 10^10 grid points:
    the design is written, the figures say why they are missing, nothing hangs or allocates terabytes."""
    text = (EXAMPLES_DIR / "zheng2015.yaml").read_text(encoding="utf-8")
    (work / "spec.yaml").write_text(text.replace("poles: [-10, -25, -50]", f"poles: {poles}"), encoding="utf-8")
    start = time.perf_counter()
    code, out, err = run(capsys, "design", "spec.yaml", "--out", "out")
    assert time.perf_counter() - start < 60
    assert code == 0, err
    assert "performance: not computed" in out
    import json

    data = json.loads((work / "out" / "zheng2015.json").read_text(encoding="utf-8"))
    assert "not_computed" in data["performance_derived"]


@pytest.mark.parametrize("rate", ["1e300", "1e999"])
def test_a_rate_beyond_float64_names_the_design_section(work, capsys, rate):
    text = (EXAMPLES_DIR / "zheng2015_min_noise.yaml").read_text(encoding="utf-8")
    text = "\n".join(f"  rate: {rate}" if line.startswith("  rate:") else line for line in text.splitlines()) + "\n"
    err = refuse(work, capsys, text, "design: a coefficient")
    assert "beyond float64" in err


def test_input_bounds_beyond_float64_name_the_design_section(work, capsys):
    text = (EXAMPLES_DIR / "aircraft_normal_form.yaml").read_text(encoding="utf-8")
    err = refuse(work, capsys, text.replace("input_bounds: [0.02]", "input_bounds: [1e999]"), "design: L is beyond 1e300")
    assert "float64" in err


def test_sta_gains_beyond_float64(work, capsys):
    text = (EXAMPLES_DIR / "bejarano2007_example1.yaml").read_text(encoding="utf-8")
    text = text.replace("gains: [[15, 10], [20, 10]]", "gains: [[1e999, 10], [20, 10]]").replace("t_final: 10", "t_final: 2.5")
    err = refuse(work, capsys, text, "simulate: gain 0.0 has magnitude about 10^999", "simulate")
    assert "beyond float64" in err
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    code, _, err = run(capsys, "design", "spec.yaml", "--out", "out")  # the exact design is fine
    assert code == 0, err


@pytest.mark.parametrize("extra", [("--out", "."), ("--out", ".", "--latex", "spec.yaml")], ids=["out", "latex"])
def test_outputs_never_replace_the_spec_itself_even_with_force(work, capsys, extra):
    text = spec(top="name: spec\n")  # outputs spec.json, spec.yaml: the latter is the spec file
    (work / "spec.yaml").write_text(text, encoding="utf-8")
    code, _, err = run(capsys, "design", "spec.yaml", *extra, "--force")
    assert_refused(code, err, extra[-2])
    assert "is the spec file itself" in err
    assert (work / "spec.yaml").read_text(encoding="utf-8") == text
