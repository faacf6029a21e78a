"""Small defects of the ``uio-ring`` command, each reproduced, and the ``example`` command."""

from __future__ import annotations

import io
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from uio_ring.cli import build_parser, main
from uio_ring.cli.examples import example_names, example_text

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
SHIPPED = ROOT / "uio_ring" / "examples"


# ------------------------------------------------------------------ uio-ring example
def test_example_list_names_every_shipped_spec(capsys):
    assert main(["example", "--list"]) == 0
    out = capsys.readouterr().out
    assert example_names() == sorted(p.stem for p in SHIPPED.glob("*.yaml"))
    for name in example_names():
        assert name in out
    assert "zheng2015" in example_names() and "aircraft_normal_form" in example_names()


def test_example_writes_into_the_current_folder_and_designs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["example", "zheng2015"]) == 0
    written = tmp_path / "zheng2015.yaml"
    assert written.read_text(encoding="utf-8") == (SHIPPED / "zheng2015.yaml").read_text(encoding="utf-8")
    assert "wrote zheng2015.yaml" in capsys.readouterr().out
    assert main(["check", "zheng2015.yaml"]) == 0


def test_example_never_overwrites_silently(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    mine = tmp_path / "zheng2015.yaml"
    mine.write_text("my own spec\n", encoding="utf-8")
    assert main(["example", "zheng2015.yaml"]) == 2
    assert "--force" in capsys.readouterr().err
    assert mine.read_text(encoding="utf-8") == "my own spec\n"
    assert main(["example", "zheng2015", "--force"]) == 0
    assert mine.read_text(encoding="utf-8") == example_text("zheng2015")


def test_example_unknown_name_exits_2_with_a_suggestion(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["example", "zheng2051"]) == 2
    err = capsys.readouterr().err
    assert "did you mean 'zheng2015'" in err and "Traceback" not in err
    assert main(["example"]) == 2  # no name: the list, on stderr
    assert "zheng2015" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_shipped_examples_equal_the_repository_examples():
    """``examples/`` (README, notebooks) and the package data must not drift apart."""
    repo = {p.name: p.read_bytes() for p in EXAMPLES.glob("*.yaml")}
    shipped = {p.name: p.read_bytes() for p in SHIPPED.glob("*.yaml")}
    assert sorted(repo) == sorted(shipped), "copy new examples/*.yaml into uio_ring/examples/ (package data)"
    for name, data in repo.items():
        assert shipped[name] == data, f"examples/{name} differs from uio_ring/examples/{name}"


def test_pyproject_ships_examples_and_plots_without_extras():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "examples/*.yaml" in meta["tool"]["setuptools"]["package-data"]["uio_ring"]
    # README: after `pip install -e .`, `uio-ring simulate` writes its PNG
    assert any(d.startswith("matplotlib") for d in meta["project"]["dependencies"])


# ------------------------------------------------------------------ item 4: small defects
def test_broken_pipe_is_quiet(monkeypatch, capsys):
    class ClosedPipe(io.StringIO):
        def write(self, s):
            raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert main(["smith", "[[d, 0], [0, d + 1]]"]) == 141


def test_design_piped_into_head_has_no_traceback(tmp_path):
    cmd = (
        f'"{sys.executable}" -m uio_ring.cli design "{EXAMPLES / "zheng2015.yaml"}" '
        f'--out "{tmp_path}" | head -n 1'
    )
    res = subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert "Traceback" not in res.stderr and "BrokenPipeError" not in res.stderr, res.stderr


@pytest.mark.parametrize("name", ["two_masses_delay_free", "aircraft_normal_form", "zheng2015"])
def test_no_python_none_in_output(name, tmp_path, capsys):
    main(["check", str(EXAMPLES / f"{name}.yaml")])
    main(["design", str(EXAMPLES / f"{name}.yaml"), "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert "None" not in out
    if name == "two_masses_delay_free":
        assert "delay-free" in out


def _with_design_line(tmp_path, line: str) -> Path:
    text = (EXAMPLES / "aircraft_normal_form.yaml").read_text(encoding="utf-8")
    spec = tmp_path / "spec.yaml"
    spec.write_text(text.replace("  input_bounds: [0.02]", line), encoding="utf-8")
    return spec


def test_negative_input_bound_names_its_path(tmp_path, capsys):
    assert main(["design", str(_with_design_line(tmp_path, "  input_bounds: [-5]")), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "design.input_bounds[0]" in err and "-5" in err
    assert main(["check", str(_with_design_line(tmp_path, "  input_bounds: -5"))]) == 2
    assert "design.input_bounds:" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("spec", "code"),
    [("double_integrator_fails.yaml", 1), ("zheng2015.yaml", 0)],
)
def test_debug_does_not_change_the_exit_code(spec, code, tmp_path, capsys):
    args = ["design", str(EXAMPLES / spec), "--out", str(tmp_path), "--force"]  # the second run replaces the files
    assert main(args) == code
    assert main(["--debug", *args]) == code


def test_debug_bad_spec_same_code_with_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("system: 1\n")
    assert main(["design", str(bad)]) == 2
    assert "Traceback" not in capsys.readouterr().err
    assert main(["--debug", "design", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" in err and "system" in err


@pytest.mark.parametrize("command", ["check", "design", "simulate", "schema", "example", "hermite", "smith"])
def test_every_command_has_a_description(command):
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    parser = sub.choices[command]
    assert parser.description and len(parser.description) > 30


def test_lag_is_not_called_a_delay_of_the_estimate(tmp_path, capsys):
    assert main(["design", str(EXAMPLES / "zheng2015.yaml"), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "delayed by" not in out
    assert "x̂(t) estimates x(t)" in out and "of history" in out


def test_design_option_errors_name_the_design_section(tmp_path, capsys):
    spec = _with_design_line(tmp_path, "  input_bounds: [0.02, 0.1]")
    assert main(["design", str(spec), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "design: input_bounds has 2 entries" in err and "Traceback" not in err


def test_quiet_prints_the_summary_and_the_files_only(tmp_path, capsys):
    """``--quiet``: the summary line and the files line, no report and no blank line before them."""
    assert main(["design", str(EXAMPLES / "zheng2015.yaml"), "--out", str(tmp_path), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2, lines
    assert lines[0].startswith("zheng2015: method zheng-bejarano, certificate ok")
    assert lines[1].startswith("wrote ") and "zheng2015.json" in lines[1]
