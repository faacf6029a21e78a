"""Sweeps: sweep files, chunks, the runner (local and dask.distributed), resumability, the CLI."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np
import pytest

pd = pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

from uio_ring.cli import main  # noqa: E402
from uio_ring.errors import SpecError  # noqa: E402
from uio_ring.sweeps import load_sweep, sweep, sweep_from_dict  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
H = [0.01, 0.011, 0.012, 0.013]  # the design's h is 0.01


def _mismatch(tmp_path: Path, **extra) -> Path:
    text = f"""
base: {EXAMPLES / "zheng2015.yaml"}
name: mismatch
seed: 3
samples: 2
chunk_size: 2
simulate: {{t_final: 1.5, dt: 0.001, settle: 1}}
axes:
  h_true: {H}
"""
    for k, v in extra.items():
        text += f"{k}: {v}\n"
    p = tmp_path / "sweep.yaml"
    p.write_text(text)
    return p


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as c:
        yield c


def test_delay_mismatch_on_two_dask_workers(tmp_path, cluster):
    """One row per run; the nominal runs are simulate_observer's; the error grows with |h_true − h|
    (the observer reads its taps at multiples of the design's h: a mismatch leaves a bias that
    does not decay, larger as the mismatch grows); 1 and 2 workers give the same table."""
    from uio_ring import simulate_observer
    from uio_ring.spec import load_spec
    from uio_ring.sweeps.runner import _design

    f = _mismatch(tmp_path)
    res = sweep(f, out=tmp_path / "dask", scheduler=cluster.scheduler_address, formats=["parquet"])
    t = res.table
    assert len(t) == 8 and list(t["run"]) == list(range(8)) and (t["error"] == "").all()
    assert res.computed == 4 and res.skipped == 0
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    r = simulate_observer(_design(spec), t_final=1.5, dt=0.001, w=spec.simulate.signal("w"),
                          x0=spec.simulate.signal("phi"))
    e = np.max(np.abs(r.error), axis=0)
    for _, row in t[t["h_true"] == 0.01].iterrows():
        assert row["peak"] == pytest.approx(e.max(), rel=1e-10)
        # the error decays by six orders: rounding of the peak's order (the batch and one run round
        # their products differently) is compared with the peak, not with the small final value
        assert row["final"] == pytest.approx(e[-1], rel=1e-8, abs=1e-12 * e.max())
        assert row["max_settled"] == pytest.approx(e[r.t >= 1 - 1e-12].max(), rel=1e-8, abs=1e-12 * e.max())
    med = t.groupby("h_true")["max_settled"].median()
    assert med[0.01] < med[0.011] / 5 and np.all(np.diff(med.to_numpy()) > 0)
    local = sweep(f, out=tmp_path / "local", workers=1, formats=["parquet"]).table
    pd.testing.assert_frame_equal(local, t)


def test_a_killed_worker_loses_no_chunk(tmp_path, cluster):
    from distributed import Client

    f = _mismatch(tmp_path)
    killed = []

    def kill_one(chunk):
        if not killed:
            with Client(cluster.scheduler_address) as c:
                pids = c.run(os.getpid)  # the worker processes this test's cluster started
            os.kill(pids[sorted(pids)[0]], signal.SIGKILL)
            killed.append(chunk.index)

    res = sweep(f, out=tmp_path / "o", scheduler=cluster.scheduler_address, formats=["parquet"], on_chunk=kill_one)
    assert killed and len(res.table) == 8 and (res.table["error"] == "").all()
    again = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet"])
    assert again.computed == 0 and again.skipped == 4


def test_a_killed_local_worker_loses_no_chunk(tmp_path, monkeypatch):
    """Local processes: SIGKILL one worker after the first chunk is written; the pool breaks,
    the written chunks stay, the rest run in a new pool; the table is the one-worker table."""
    import concurrent.futures
    import multiprocessing as mp

    pools = []

    class CountedPool(concurrent.futures.ProcessPoolExecutor):
        def __init__(self, *args, **kwargs):
            pools.append(self)
            super().__init__(*args, **kwargs)

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", CountedPool)
    others = {p.pid for p in mp.active_children()}  # e.g. the dask cluster of other tests: not ours to kill
    f = _mismatch(tmp_path)
    f.write_text(f.read_text().replace("chunk_size: 2", "chunk_size: 1"))  # 8 chunks: some are left at the kill
    killed = []

    def kill_one(chunk):
        workers = [p for p in mp.active_children() if p.pid is not None and p.pid not in others]
        if not killed and workers:
            os.kill(workers[0].pid, signal.SIGKILL)
            killed.append(chunk.index)

    res = sweep(f, out=tmp_path / "o", workers=2, formats=["parquet"], on_chunk=kill_one)
    assert killed and len(res.table) == 8 and (res.table["error"] == "").all()
    assert res.computed == 8 and len(pools) == 2  # the broken pool was replaced once
    one = sweep(f, out=tmp_path / "one", workers=1, formats=["parquet"]).table
    pd.testing.assert_frame_equal(one, res.table)
    again = sweep(f, out=tmp_path / "o", workers=2, formats=["parquet"])
    assert again.computed == 0 and again.skipped == 8


def _dies_on_chunk_1(task):
    """A chunk runner whose process dies on chunk 1 (every time) and works on the others."""
    from uio_ring.sweeps.runner import run_chunk

    if task["chunk"].index == 1:
        os.kill(os.getpid(), signal.SIGKILL)
    return run_chunk(task)


def test_a_chunk_whose_worker_always_dies_is_rows_with_the_reason(tmp_path):
    """Only that chunk is charged (it is found by running the chunks left one at a time); the
    others complete and match the one-worker table (to rounding: a process started with
    OPENBLAS_NUM_THREADS=1, as after a dask cluster, rounds some products differently)."""
    from uio_ring.sweeps.runner import _run_local

    f = _mismatch(tmp_path)
    sw = load_sweep(f)
    common = {"axes": [a.name for a in sw.axes], "base": sw.base, "options": list(sw.design_options),
              "tol": sw.tol, "diverge": sw.diverge, "fingerprint": sw.fingerprint()}
    tasks = [dict(common, chunk=c) for c in sw.chunks()]
    rows = {}
    _run_local(tasks, 2, lambda t, r: rows.__setitem__(t["chunk"].index, r), run=_dies_on_chunk_1)
    assert sorted(rows) == [0, 1, 2, 3]
    assert all(r["error"].startswith("WorkerDied") and np.isnan(r["peak"]) for r in rows[1])
    assert all(r["error"] == "" for c in (0, 2, 3) for r in rows[c])
    one = sweep(f, out=tmp_path / "one", workers=1, formats=["parquet"]).table
    for c in (0, 2, 3):
        for r in rows[c]:
            assert r["peak"] == pytest.approx(one.loc[one["run"] == r["run"], "peak"].item(), rel=1e-12)


def test_noise_gain_is_the_design_figure(tmp_path):
    """One figure, one name: the sweep's noise_gain is design.performance()'s peak-to-peak gain."""
    from uio_ring.spec import load_spec
    from uio_ring.sweeps.runner import _design

    f = _mismatch(tmp_path)
    t = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet"]).table
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    expected = float(_design(spec).performance(h=spec.system.h).noise_gain.max())
    assert np.all(t["noise_gain"] == expected) and expected > 1


def test_resumable_and_reproducible(tmp_path):
    f = _mismatch(tmp_path)
    first = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet", "csv"])
    files = sorted((tmp_path / "o" / "chunks").glob("chunk-*.parquet"))
    assert len(files) == 4 and (tmp_path / "o" / "mismatch.csv").exists()
    files[2].unlink()  # as if the run had stopped before this chunk
    again = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet"])
    assert (again.computed, again.skipped) == (1, 3)
    pd.testing.assert_frame_equal(first.table, again.table)


def test_failing_runs_are_rows(tmp_path):
    f = _mismatch(tmp_path)
    f.write_text(f.read_text().replace("h_true: [", "h_true: [0.0105, "))  # dt = 0.001 does not divide it
    res = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet", "png"])
    t = res.table
    assert [p.name for p in res.plots] == ["mismatch_errors.png", "mismatch_convergence.png"]
    assert all(p.stat().st_size > 1000 for p in res.plots)
    bad = t[t["h_true"] == 0.0105]
    assert len(t) == 10 and len(bad) == 2
    assert bad["error"].str.contains("dt=0.001 is not h/N").all() and bad["peak"].isna().all()
    assert (t[t["h_true"] != 0.0105]["error"] == "").all()


def test_axes_and_draws():
    base = {"system": {"A": [[-1]], "B": [[1]], "C": [[1]], "D": [[1]]}, "simulate": {"t_final": 1, "dt": "0.01"}}
    sw = sweep_from_dict({"base": base, "seed": 5, "samples": 3, "chunk_size": 2,
                          "axes": {"noise": {"linspace": [0, 1, 2]}, "x0_random": {"uniform": [0, 1]},
                                   "w_family": {"choice": ["sine", "pwc"]}}})
    runs = sw.runs()
    assert [r.params["noise"] for r in runs] == [0.0] * 3 + [1.0] * 3
    assert runs == sw.runs() and len({r.seed for r in runs}) == 6
    assert all(0 <= r.params["x0_random"] <= 1 and r.params["w_family"] in ("sine", "pwc") for r in runs)
    assert [len(c.runs) for c in sw.chunks()] == [2, 2, 2]  # one plant: chunks of chunk_size


@pytest.mark.parametrize("axes, match", [
    ({"h_tru": [1]}, r"axes\.h_tru: unknown axis"),
    ({"noise": {"gauss": [0, 1]}}, r"axes\.noise: unknown axis kind 'gauss'"),
    ({"noise": {"linspace": [0, 1]}}, r"axes\.noise\.linspace: expected \[start, stop, count"),
    ({"noise": [-1]}, r"axes\.noise\.grid\[0\]: noise must be ≥ 0"),
    ({"w_family": ["saw"]}, r"unknown family 'saw'"),
    ({"h_true": {"loguniform": [0, 1]}}, r"axes\.h_true\.loguniform: expected 0 < low ≤ high"),
])
def test_bad_axes(axes, match):
    base = {"system": {"A": [[-1]], "B": [[1]], "C": [[1]], "D": [[1]]}, "simulate": {"t_final": 1, "dt": "0.01"}}
    with pytest.raises(SpecError, match=match):
        sweep_from_dict({"base": base, "axes": axes})


def test_cli_sweep(tmp_path, capsys):
    f = _mismatch(tmp_path)
    assert main(["sweep", str(f), "--out", str(tmp_path / "o"), "--workers", "1", "--csv", "--no-plot",
                 "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "mismatch: 8 runs (4 chunks computed, 0 found done)" in out and "mismatch.csv" in out
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"base: {EXAMPLES / 'zheng2015.yaml'}\naxes: {{h_true: [0.01]}}\nchunks: 3\n")
    assert main(["sweep", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(bad) in err[0] and "chunks" in err[0]
    with pytest.raises(SpecError, match="no such file"):
        load_sweep(tmp_path / "missing.yaml")


def test_local_processes_give_the_same_table(tmp_path):
    f = _mismatch(tmp_path)
    two = sweep(f, out=tmp_path / "two", workers=2, formats=["parquet"]).table
    one = sweep(f, out=tmp_path / "one", workers=1, formats=["parquet"]).table
    pd.testing.assert_frame_equal(one, two)


def test_perturbations_families_and_design_options(tmp_path):
    """Every kind of axis gives rows; a design that fails is a row per run with its error."""
    f = tmp_path / "s.yaml"
    f.write_text(f"""
base: {EXAMPLES / "zheng2015.yaml"}
name: kinds
simulate: {{t_final: 0.6, dt: 0.001, settle: 0.4}}
chunk_size: 4
axes:
  perturbation: [0, 0.05]
  w_family: [base, sine, step, pwc, zero]
  poles: [[-10, -25, -50], [-10, -10, -10, -10, -10]]
""")
    t = sweep(f, out=tmp_path / "o", workers=1, formats=["parquet"]).table
    assert len(t) == 20
    ok, bad = t[t["poles"] == "[-10, -25, -50]"], t[t["poles"] != "[-10, -25, -50]"]
    assert (ok["error"] == "").all() and bad["error"].str.startswith("DimensionError: poles has 5").all()
    assert bad["peak"].isna().all()
    assert np.isfinite(ok["peak"]).all()
    nominal = ok[ok["perturbation"] == 0].set_index("w_family")["max_settled"]
    perturbed = ok[ok["perturbation"] == 0.05].set_index("w_family")["max_settled"]
    assert (perturbed > nominal).all()  # a perturbed plant leaves a bias the observer cannot see


def test_the_example_sweep_file_loads():
    sw = load_sweep(EXAMPLES / "sweeps" / "zheng2015_delay_sweep.yaml")
    assert sw.grid_axes == ["h_true"] and len(sw.runs()) == 20 and len(sw.chunks()) == 3  # h_true shares chunks


def test_cli_sweep_on_a_scheduler(tmp_path, capsys, cluster):
    f = _mismatch(tmp_path)
    assert main(["sweep", str(f), "--out", str(tmp_path / "o"), "--scheduler", cluster.scheduler_address,
                 "--no-plot", "--quiet"]) == 0
    assert "mismatch: 8 runs (4 chunks computed, 0 found done); 2 converged" in capsys.readouterr().out


@pytest.mark.parametrize("top, match", [
    ("name: ../evil\n", r"name: '../evil' is not a safe file name"),
    ("output: {directory: ../elsewhere}\n", r"output.directory: '../elsewhere': expected a folder inside"),
    ("output: {directory: /tmp/x}\n", r"output.directory: '/tmp/x'"),
])
def test_files_stay_in_their_folder(tmp_path, top, match):
    f = tmp_path / "s.yaml"
    f.write_text(f"base: {EXAMPLES / 'zheng2015.yaml'}\n{top}")
    with pytest.raises(SpecError, match=match):
        load_sweep(f)


def test_perturbations_share_a_batch_and_keep_the_numbers(tmp_path, monkeypatch):
    """Runs on differently perturbed plants form one chunk (one batch, a plant per scenario); the
    table has the numbers of the former grouping (one chunk per perturbed plant) to rounding."""
    import uio_ring.sweeps.spec as spec_mod

    f = tmp_path / "p.yaml"
    f.write_text(f"""
base: {EXAMPLES / "zheng2015.yaml"}
name: pert
seed: 2
samples: 2
chunk_size: 16
simulate: {{t_final: 0.6, dt: 0.0005, settle: 0.4}}
axes:
  perturbation: [0, 0.02, 0.05]
  perturbation_seed: [0, 1]
  noise: {{uniform: [0, 0.01]}}
""")
    sw = load_sweep(f)
    assert [len(c.runs) for c in sw.chunks()] == [12]
    new = sweep(f, out=tmp_path / "new", workers=1, formats=["parquet"]).table
    monkeypatch.setattr(spec_mod, "PER_SCENARIO_PLANT_AXES", ())  # the former grouping: one chunk per plant
    assert len(load_sweep(f).chunks()) == 6
    old = sweep(f, out=tmp_path / "old", workers=1, formats=["parquet"]).table
    assert (new["error"] == "").all() and (old["error"] == "").all()
    assert len(new) == 12 and (new["chunk"] == 0).all()
    for col in ("run", "seed", "perturbation", "perturbation_seed", "noise", "noise_gain", "t_converge"):
        pd.testing.assert_series_equal(new[col], old[col])
    for col in ("max_after", "rms_after", "peak", "t_peak", "final", "max_settled", "rms_settled"):
        np.testing.assert_allclose(new[col], old[col], rtol=1e-10, atol=0)
    assert new.groupby("perturbation")["max_settled"].mean().is_monotonic_increasing
