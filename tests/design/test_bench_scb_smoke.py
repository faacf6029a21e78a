"""Smoke test: benchmarks/bench_scb.py runs in --quick mode (no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_scb.py"


def test_bench_scb_quick_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--quick"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "Tranninger2021 example" in proc.stdout and "FAILED" not in proc.stdout
    assert proc.stdout.count(" ok ") == 3  # every certificate holds
