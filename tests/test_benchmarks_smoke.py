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
