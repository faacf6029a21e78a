"""Long simulations are streamed to CSV by segments: the same file, bounded memory, the same refusals."""

from __future__ import annotations

import csv
import re
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import uio_ring.cli.stream as stream
from uio_ring.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SMALL = """name: small
system:
  A: [[0, 1], [-1, -d]]
  B: [[0], [1]]
  C: [[1, 0], [0, 1]]
  h: 0.1
design:
  poles: [-2]
simulate:
  t_final: {t_final}
  dt: 0.01
  w: ['sin(t) + step(t - 1.234)']
  phi: ['cos(t)', 0]
  noise: {{bound: 0.01, seed: 4}}
"""


def _csv(path: Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)


def _simulate(capsys, spec: Path, out: Path, *extra: str) -> tuple[int, str, str]:
    code = main(["simulate", str(spec), "--out", str(out), "--no-progress", *extra])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


@pytest.mark.parametrize("name", ["zheng2015.yaml", "aircraft_normal_form.yaml"])
def test_streamed_csv_is_the_in_memory_csv(tmp_path, capsys, monkeypatch, name):
    """Same header, same rows (to rounding: the batch engine is simulate_observer's recursion by
    segments), same summary figures; the streamed run also draws its plot from a preview."""
    spec = tmp_path / name
    text = (EXAMPLES / name).read_text(encoding="utf-8").replace("t_final: 6", "t_final: 3")
    spec.write_text(text, encoding="utf-8")
    code, out_mem, err = _simulate(capsys, spec, tmp_path / "mem", "--no-plot")
    assert code == 0, err
    monkeypatch.setattr(stream, "STREAM_VALUES", 0)
    monkeypatch.setattr(stream, "PREVIEW_POINTS", 100)
    code, out_str, err = _simulate(capsys, spec, tmp_path / "str")
    assert code == 0, err
    assert "(streamed to disk)" in out_str and "(streamed" not in out_mem
    stem = spec.stem
    h1, a = _csv(tmp_path / "mem" / f"{stem}.csv")
    h2, b = _csv(tmp_path / "str" / f"{stem}.csv")
    assert h1 == h2 and a.shape == b.shape
    assert np.all(a[:, 0] == b[:, 0])
    assert np.abs(a - b).max() <= 1e-8 * max(np.abs(a).max(), 1.0)
    assert (tmp_path / "str" / f"{stem}.png").stat().st_size > 0
    figures = [[float(v) for v in re.findall(r"(?<=[ :])-?\d[\d.e+-]*(?=[,;( ]|$)", line)]
               for text in (out_mem, out_str) for line in text.splitlines() if "simulated" in line]
    assert len(figures[0]) == len(figures[1]) >= 4  # t_final, dt, steps, final error, settle, max error, …
    assert np.allclose(figures[0], figures[1], rtol=1e-2, atol=1e-8 * np.abs(a).max())  # 3 printed digits


def test_streamed_run_with_noise_and_a_jump(tmp_path, capsys, monkeypatch):
    """Noise (the same seeded stream), an input step between samples, several segments."""
    spec = tmp_path / "small.yaml"
    spec.write_text(SMALL.format(t_final=5), encoding="utf-8")
    assert _simulate(capsys, spec, tmp_path / "mem", "--no-plot")[0] == 0
    monkeypatch.setattr(stream, "STREAM_VALUES", 0)
    real = stream.stream_csv
    monkeypatch.setattr(stream, "stream_csv", lambda *a, **k: real(*a, **{**k, "segment_steps": 40}))
    assert _simulate(capsys, spec, tmp_path / "str", "--no-plot")[0] == 0
    _, a = _csv(tmp_path / "mem" / "small.csv")
    _, b = _csv(tmp_path / "str" / "small.csv")
    assert a.shape == b.shape == (501, 10)
    assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max()


@pytest.mark.parametrize("text,where,reason", [
    ("system:\n  A: [[-1000000, 0], [1, -1]]\n  B: [[0], [1]]\n  C: [[1, 0], [0, 1]]\ndesign:\n  poles: [-1]\n"
     "simulate:\n  t_final: 1\n  dt: 0.01\n  w: ['sin(t)']\n  phi: [1, 0]\n", "simulate.dt", "not resolved"),
    (SMALL.format(t_final=30).replace("sin(t) + step(t - 1.234)", "1e300*exp(100*t)"), "simulate", "not finite"),
])
def test_streamed_runs_refuse_what_in_memory_runs_refuse(tmp_path, capsys, monkeypatch, text, where, reason):
    monkeypatch.setattr(stream, "STREAM_VALUES", 0)
    spec = tmp_path / "s.yaml"
    spec.write_text("name: s\n" + text if not text.startswith("name") else text, encoding="utf-8")
    code, _, err = _simulate(capsys, spec, tmp_path / "o")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith(f"uio-ring: error: {where}: ") and reason in err
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


def _peak(spec_text: str, tmp_path: Path, steps: int) -> int:
    from uio_ring.cli.spec_commands import _check_finite, _design
    from uio_ring.spec import load_spec_text

    spec = load_spec_text(spec_text.format(t_final=steps // 100))
    design = _design(spec)[0]
    tracemalloc.start()
    try:
        stream.stream_csv(design, spec, tmp_path / f"{steps}.csv", settle=0.0, check=_check_finite,
                          preview=True, segment_steps=500)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_streamed_memory_does_not_grow_with_the_steps(tmp_path, monkeypatch):
    """Peak traced memory for 4× the steps grows by less than a tenth of what the in-memory
    record would grow by (10 columns of float64 per step).  The fixed windows (input samples,
    segments, preview) are made small so that a growth would show."""
    import uio_ring.sim.batch as batch

    monkeypatch.setattr(stream, "PREVIEW_POINTS", 200)
    monkeypatch.setattr(batch, "INPUT_WINDOW", 1 << 12)
    _peak(SMALL, tmp_path, 1_000)  # once for the caches made on first use
    short, long = _peak(SMALL, tmp_path, 10_000), _peak(SMALL, tmp_path, 40_000)
    record_growth = 30_000 * 10 * 8
    assert long - short < 0.1 * record_growth, (short, long)
    assert (tmp_path / "40000.csv").stat().st_size > 3.5 * (tmp_path / "10000.csv").stat().st_size
