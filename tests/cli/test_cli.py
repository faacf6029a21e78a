"""The uio-ring command: exit codes, messages without tracebacks, written files."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from uio_ring.cli import main
from uio_ring.spec import load_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_design_paper_example(tmp_path, capsys):
    code = main(["design", str(EXAMPLES / "zheng2015.yaml"), "--out", str(tmp_path), "--latex", str(tmp_path / "d.tex")])
    out = capsys.readouterr().out
    assert code == 0
    assert "certificate ok" in out and "n_z = 6" in out
    assert "Assumption 1" in out and "Assumption 2" in out
    design = load_design(tmp_path / "zheng2015.json")
    assert design == load_design(tmp_path / "zheng2015.yaml")
    assert design.certificate().ok and design.n_z <= 6 and design.lag <= 4
    assert (tmp_path / "d.tex").read_text().strip()


def test_failing_assumption_exits_1_and_says_why(tmp_path, capsys):
    code = main(["design", str(EXAMPLES / "double_integrator_fails.yaml"), "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 1
    assert "Assumption 2" in err and "Traceback" not in err


def test_check_reports_both_ways(capsys):
    assert main(["check", str(EXAMPLES / "zheng2015.yaml")]) == 0
    assert "applicable" in capsys.readouterr().out
    assert main(["check", str(EXAMPLES / "double_integrator_fails.yaml")]) == 1
    assert "NOT applicable" in capsys.readouterr().out


def test_bad_spec_exits_2_with_the_path(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("system:\n  A: [[0, 1], [0, 0]]\n  B: [[0], [1]]\n  C: [['1+*d', 0]]\n  h: 1\n")
    assert main(["design", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "system.C[0][0]: cannot parse '1+*d' at column 3" in err and "Traceback" not in err


def test_debug_shows_the_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("system: 1\n")
    assert main(["--debug", "design", str(bad)]) == 2  # same exit code as without --debug
    err = capsys.readouterr().err
    assert "Traceback" in err and "system" in err


def test_calculator_commands(capsys):
    assert main(["smith", "[[d, 0], [0, d + 1]]", "--transforms"]) == 0
    out = capsys.readouterr().out
    assert "invariant factors: 1, d**2 + d" in out and "check U·M·V == S: True" in out
    assert main(["hermite", "[[d**2, d], [d, 1]]", "--latex"]) == 0
    assert r"\delta" in capsys.readouterr().out
    assert main(["hermite", "[[1+*d]]"]) == 2


def test_schema_command_prints_the_schema(capsys):
    assert main(["schema"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["required"] == ["system"]


def test_simulate_writes_csv_png_and_summary(tmp_path, capsys):
    code = main(["simulate", str(EXAMPLES / "zheng2015.yaml"), "--out", str(tmp_path), "--no-progress"])
    out = capsys.readouterr().out
    assert code == 0
    assert (tmp_path / "zheng2015.csv").exists() and (tmp_path / "zheng2015.png").exists()
    line = [s for s in out.splitlines() if "max error after" in s][0]
    max_err = float(line.rsplit(":", 1)[1])
    assert max_err < 1e-4  # exact-design observer: error at integration level after 2 s


def test_console_script_runs():
    proc = subprocess.run(
        [sys.executable, "-m", "uio_ring.cli", "smith", "[[d, 1], [0, d]]"], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 0 and "d**2" in proc.stdout


def test_auto_picks_the_normal_form_for_the_aircraft_and_says_why(tmp_path, capsys):
    text = (EXAMPLES / "aircraft_normal_form.yaml").read_text().replace("method: normal-form", "method: auto")
    text = text.split("simulate:")[0]
    spec = tmp_path / "aircraft_auto.yaml"
    spec.write_text(text)
    assert main(["design", str(spec), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "method normal-form, certificate ok" in out
    skipped = [line for line in out.splitlines() if line.startswith("auto skipped zheng-bejarano")]
    assert skipped and "Assumption 2" in skipped[0]
    design = load_design(tmp_path / "aircraft_normal_form.json")  # named by the spec
    assert design.method == "normal-form" and design.certificate().ok
    assert design.mu == (4, 3)


def test_auto_without_input_bounds_names_the_missing_option(tmp_path, capsys):
    """Without input bounds the normal form is skipped (and auto says why); the aircraft is
    strongly observable, so the hierarchical super-twisting observer applies."""
    text = (EXAMPLES / "aircraft_normal_form.yaml").read_text().split("design:")[0]
    spec = tmp_path / "aircraft_nobounds.yaml"
    spec.write_text(text + "design:\n  method: auto\n")
    assert main(["design", str(spec), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "auto skipped normal-form: needs design option(s) input_bounds" in out
    assert "auto skipped zheng-bejarano" in out and "method hierarchical-sta, certificate ok" in out


def _max_error_after_settle(out: str) -> float:
    import re

    return float(re.search(r"max error after t = [\d.]+ s: ([\d.e+-]+)", out).group(1))


def test_min_noise_example_lowers_the_simulated_error(tmp_path, capsys):
    """The noisy example of paper 001 with the paper's poles and with poles='min-noise': the
    design output states the noise gain, and the simulated error after the start-up falls
    (measured 135 → 10.2, 13×; the guaranteed peak-to-peak gain falls 9.5×, 327.8 → 34.7)."""
    peaks = []
    for name in ("zheng2015_noisy.yaml", "zheng2015_min_noise.yaml"):
        code = main(["simulate", str(EXAMPLES / name), "--out", str(tmp_path / name), "--no-plot", "--no-progress"])
        out = capsys.readouterr().out
        assert code == 0
        peaks.append(_max_error_after_settle(out))
    assert peaks[1] * 5 <= peaks[0], peaks
    assert main(["design", str(EXAMPLES / "zheng2015_min_noise.yaml"), "--out", str(tmp_path / "d")]) == 0
    assert "noise gain per state" in capsys.readouterr().out


def test_check_previews_the_design_and_names_other_methods(tmp_path, capsys):
    """check prints what the zheng-bejarano design will be (n_z, how many poles, the default
    poles); when the chosen method refuses and another applies, it says which."""
    assert main(["check", str(EXAMPLES / "zheng2015.yaml")]) == 0
    out = capsys.readouterr().out
    assert "smallest observer: n_z = 6; poles takes l* = 2 or 3 value(s)" in out and "at -4" in out
    text = (EXAMPLES / "aircraft_normal_form.yaml").read_text().replace("method: normal-form", "method: zheng-bejarano")
    text = "\n".join(line for line in text.splitlines() if "input_bounds" not in line and "reconstruct_input" not in line)
    spec = tmp_path / "air.yaml"
    spec.write_text(text)
    assert main(["check", str(spec)]) == 1
    out = capsys.readouterr().out
    assert "method normal-form applies to this system (needs the option(s) input_bounds)" in out


def test_long_checks_say_what_is_taking_long(tmp_path, capfd, monkeypatch):
    """Exact algebra on large, high-degree systems can take minutes: a line on stderr every
    HEARTBEAT_SECONDS says what runs (here shortened, and the check slowed down: a 4×4,
    δ-degree-4 check now takes well under a second)."""
    import random
    import time

    import uio_ring.cli.heartbeat as hb
    from uio_ring.design.methods import DesignMethod

    monkeypatch.setattr(hb, "HEARTBEAT_SECONDS", 0.05)
    applies = DesignMethod.applies

    def slow_applies(self, sys):
        time.sleep(0.3)
        return applies(self, sys)

    monkeypatch.setattr(DesignMethod, "applies", slow_applies)
    rng = random.Random(1)

    def mat(r, c):
        return "[" + ", ".join("[" + ", ".join(" + ".join(f"({rng.randint(-3, 3)})*d**{k}" for k in range(5))
                                               for _ in range(c)) + "]" for _ in range(r)) + "]"

    spec = tmp_path / "big.yaml"
    spec.write_text(f"system:\n  A: {mat(4, 4)}\n  B: {mat(4, 2)}\n  C: {mat(3, 4)}\n  h: 0.1\n")
    main(["check", str(spec)])
    err = capfd.readouterr().err  # the lines come from a child process: captured at the fd
    assert "uio-ring: still checking method zheng-bejarano (4 states, δ-degree 4" in err and "Ctrl-C stops" in err


@pytest.mark.parametrize("command", ["hermite", "smith"])
def test_the_calculator_says_which_step_is_taking_long(capfd, monkeypatch, command):
    """At its limits the calculator runs for up to a minute: a line on stderr every
    HEARTBEAT_SECONDS names the form, the matrix and the step (here shortened, with the
    form and then the exact check slowed down)."""
    import time

    import uio_ring.cli.heartbeat as hb
    import uio_ring.ring as ring

    monkeypatch.setattr(hb, "HEARTBEAT_SECONDS", 0.05)
    real = getattr(ring, command)

    def slow_form(M):
        result = real(M)
        time.sleep(0.4)
        slow_verify = result.verify
        object.__setattr__(result, "verify", lambda M: time.sleep(0.4) or slow_verify(M))
        return result

    monkeypatch.setattr(ring, command, slow_form)
    assert main([command, "--transforms", "[[d, 1], [d**2 + 1, d]]"]) == 0
    out, err = capfd.readouterr()
    form = {"hermite": "Hermite", "smith": "Smith"}[command]
    assert f"uio-ring: still computing the {form} form of a 2×2 matrix of δ-degree 2" in err
    assert "— the form and its transform" in err and "— checking U·M" in err
    assert "check U·M" in out and "True" in out.splitlines()[-1]


def test_heartbeat_keeps_beating_while_one_call_holds_the_interpreter(capfd, monkeypatch):
    """One call into C (FLINT's solves can take minutes) holds the interpreter, so no thread
    of this process can print; the heartbeat's lines come from a forked child, with the
    latest progress note.  Here ``sum(range(N))`` holds it for more than half a second
    (N doubles until it does: the machine's speed varies)."""
    import time

    import uio_ring.cli.heartbeat as hb
    from uio_ring import _progress

    monkeypatch.setattr(hb, "HEARTBEAT_SECONDS", 0.05)
    n, held, err = 10**7, 0.0, ""
    with hb.Heartbeat("testing the heartbeat"):
        with _progress.step("step 7: a long call"):
            while held <= 0.5 and n < 10**11:  # one pass of C, longer until it holds > 0.5 s
                n *= 2
                capfd.readouterr()  # only the lines printed during this call count
                start = time.monotonic()
                sum(range(n))
                held = time.monotonic() - start
                err = capfd.readouterr().err
    lines = [x for x in err.splitlines()
             if x.startswith("uio-ring: still testing the heartbeat") and x.endswith("— step 7: a long call")]
    assert held > 0.5 and len(lines) >= 3, (held, err)
    assert _progress.current() == ""


def test_check_and_the_calculator_do_not_import_numpy():
    """``uio-ring check`` and the calculator commands are exact algebra: numpy (about 0.1 s
    of start-up) is imported only by what evaluates numbers — the signals of a spec when a
    simulation runs, the designs' float models.  Every shipped example, in one fresh
    interpreter, with the parsed signals and nonlinearities unevaluated."""
    code = (
        "import io, sys, contextlib\n"
        "from importlib import resources\n"
        "from uio_ring.cli import main\n"
        "codes = []\n"
        "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
        "    for f in sorted(resources.files('uio_ring.examples').iterdir()):\n"
        "        if f.name.endswith('.yaml'):\n"
        "            codes.append(main(['check', str(f)]))\n"
        "    codes.append(main(['smith', '[[d, 1], [0, d + 1]]']))\n"
        "    codes.append(main(['hermite', '[[d**2, d], [d, 1]]']))\n"
        "print(len(codes), max(codes), 'numpy' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert int(out[0]) >= 10 and int(out[1]) <= 1, out  # every command ran (0, or 1: an assumption fails)
    assert out[2] == "False", out
