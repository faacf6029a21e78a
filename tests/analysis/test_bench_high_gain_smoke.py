"""Smoke test: the high-gain benchmark runs to completion in --quick mode (no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_high_gain.py"


def test_bench_high_gain_quick_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--quick"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    out = proc.stdout
    assert "paper Example 1" in out and "paper Example 2" in out and "n=5 example-2-like" in out
    assert "FAIL" not in out
