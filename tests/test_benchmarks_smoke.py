"""Smoke test: the ring benchmark runs to completion in --quick mode (no timing asserts)."""

from __future__ import annotations

import os
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
    assert "every result verified" in out and "invariant factors, H, S" in out
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


def _bench_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("bench_ring", BENCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_worker_in_another_interpreter_reports_verified_results_and_sizes():
    """The --sage-python channel (JSON over a subprocess's stdio), here with our own
    library in a fresh interpreter: every result comes back verified, with sizes
    equal to those measured in this process."""
    br = _bench_module()
    case = br.build_cases([3], 7, families=["tall"])[0]
    ops = ["hermite", "left_kernel", "left_inverse"]
    got = br.run_case("ours", case, ops, 1, 60.0, python=sys.executable)
    assert set(got) == set(ops)
    for op in ops:
        assert got[op]["ok"] is True and got[op]["t"] >= 0, got[op]
    from uio_ring import PolyMatrix, left_kernel

    M = PolyMatrix.from_coefficients(br._coefficient_matrices(case["M"], *case["shape"]))
    K = left_kernel(M)
    entries = [[[(c.numerator, c.denominator) for c in K[i, j].coeffs()] for j in range(K.cols)]
               for i in range(K.rows)]
    assert tuple(got["left_kernel"]["size"]["K"]) == br.matrix_size(entries)
    assert got["left_kernel"]["canon"] == br._row_degrees(entries)


def test_matrix_size_is_invariant_under_row_scaling():
    br = _bench_module()
    row = [[(1, 2), (3, 4)], [(5, 6)]]
    scaled = [[(7 * p, 3 * q) for p, q in e] for e in row]
    assert br.matrix_size([row]) == br.matrix_size([scaled]) == (1, 4, 11)  # 6, 9, 10 after scaling by 12: 3 + 4 + 4 bits


def test_sage_required_but_missing_exits_2(tmp_path):
    missing = str(tmp_path / "no-such-python")
    proc = subprocess.run([sys.executable, str(BENCH), "--quick", "--sage", "--sage-python", missing],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "not importable" in proc.stdout


def test_small_cells_worker_times_every_cell_and_needs_sage_for_the_table():
    import json

    script = BENCH.parent / "bench_small_cells.py"
    proc = subprocess.run([sys.executable, str(script), "--worker", "ours"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    times = json.loads(proc.stdout.strip().splitlines()[-1])
    assert "rankdef 4 hermite" in times and all(t > 0 for t in times.values())
    env = {k: v for k, v in os.environ.items() if k != "UIO_SAGE_PYTHON"}
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60, env=env)
    assert proc.returncode == 2 and "--sage-python" in proc.stderr


def test_count_instructions_runs_its_workers_under_valgrind_and_divides_by_the_calls(tmp_path):
    """A stand-in ``valgrind`` on PATH runs the worker command it is given (the real
    worker: case built, operation called) and reports 4 000 000 instructions per call
    counted; the table then reads 4.00 M.  Without valgrind, or with a malformed cell:
    exit 2 and one line."""
    script = BENCH.parent / "count_instructions.py"
    fake = tmp_path / "valgrind"
    fake.write_text(
        "#!" + sys.executable + "\n"
        "import subprocess, sys\n"
        "cmd = [a for a in sys.argv[1:] if not a.startswith('--') or a == '--worker']\n"
        "got = subprocess.run(cmd, capture_output=True, text=True)\n"
        "sys.stderr.write(got.stderr)\n"
        "sys.stderr.write('==1== Collected : %d\\n' % (4000000 * int(cmd[-1])))\n"
        "sys.exit(got.returncode)\n")
    fake.chmod(0o755)
    env = dict(os.environ, PATH=f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    env.pop("UIO_SAGE_PYTHON", None)
    proc = subprocess.run([sys.executable, str(script), "paper001:6:6x4:hermite", "--calls", "2"],
                          capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "paper001:6:6x4:hermite" in proc.stdout and "4.00" in proc.stdout
    no_valgrind = dict(env, PATH=str(Path(sys.executable).parent))
    proc = subprocess.run([sys.executable, str(script), "paper001:6:6x4:hermite"],
                          capture_output=True, text=True, timeout=60, env=no_valgrind)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "valgrind" in proc.stderr
    proc = subprocess.run([sys.executable, str(script), "paper001-6-hermite"],
                          capture_output=True, text=True, timeout=60, env=env)
    assert proc.returncode == 2 and "family:n:RxC:operation" in proc.stderr
