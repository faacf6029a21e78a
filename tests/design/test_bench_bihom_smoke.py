"""Smoke test: benchmarks/bench_bihom_dt.py runs in --quick mode (no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_bihom_dt.py"


def test_bench_bihom_quick_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--quick"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert proc.stdout.count("fitted order") == 4 and "diverged" not in proc.stdout
