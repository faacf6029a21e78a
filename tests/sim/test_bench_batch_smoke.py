"""Smoke test: benchmarks/bench_batch.py runs in --quick mode (no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_batch.py"


def test_bench_batch_quick_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--quick"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "scenario-steps/s" in proc.stdout and "aircraft" in proc.stdout and "K plants" in proc.stdout
