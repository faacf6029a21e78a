"""Smoke test: the ring benchmark runs to completion in --quick mode (no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_ring.py"


def test_bench_ring_quick_runs():
    proc = subprocess.run(
        [sys.executable, str(BENCH), "--quick"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    out = proc.stdout
    assert "ours [s]" in out and "invariant_factors" in out
    assert "invariant factors agree" in out
    assert "import cost" in out


def test_random_spec_generates_a_loadable_spec_and_times_a_check(tmp_path):
    script = BENCH.parent / "random_spec.py"
    text = subprocess.run([sys.executable, str(script), "--n", "2", "--degree", "2"],
                          capture_output=True, text=True, timeout=60, check=True).stdout
    from uio_ring.spec import load_spec_text

    spec = load_spec_text(text)
    assert spec.system.n_x == 2 and spec.system.max_delay_degree <= 2
    proc = subprocess.run([sys.executable, str(script), "--time", "2", "--degree", "2"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and "n =  2:" in proc.stdout and "CPU" in proc.stdout, proc.stdout + proc.stderr
