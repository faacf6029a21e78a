"""Smoke test: the design benchmark runs in --quick mode and every certificate holds
(no timing asserts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_design.py"


def test_bench_design_quick_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--quick"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "Zheng et al. (2015)" in proc.stdout and "FAIL" not in proc.stdout


def test_bench_design_spec_is_a_designable_spec(tmp_path):
    from uio_ring import check_assumptions
    from uio_ring.spec import load_spec

    proc = subprocess.run([sys.executable, str(BENCH), "--spec", "4", "--degree", "1"], capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    path = tmp_path / "spec.yaml"
    path.write_text(proc.stdout, encoding="utf-8")
    spec = load_spec(path)
    assert spec.system.n_x == 4 and check_assumptions(spec.system).holds
