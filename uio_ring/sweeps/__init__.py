"""Robustness sweeps: many runs of one design over delay mismatch, perturbations, noise, inputs.

``uio_ring.sweep(file)`` (this package: ``uio_ring.sweeps``) and ``uio-ring sweep file.yaml`` read a sweep file
(:mod:`uio_ring.sweeps.spec`), cut its runs into chunks that share a plant and a design,
run each chunk as one batched simulation (:func:`uio_ring.sim.batch.simulate_batch`) in
local processes or on a ``dask.distributed`` cluster, and write a tidy table (Parquet,
CSV on request; one row per run with its parameters, seed and metrics) and summary
plots.  Needs the extra ``sweep`` (pandas, pyarrow, dask.distributed for ``--scheduler``).
"""

from uio_ring.sweeps.runner import SweepResult, run_chunk, sweep
from uio_ring.sweeps.spec import SweepSpec, load_sweep, sweep_from_dict

__all__ = ["sweep", "SweepResult", "SweepSpec", "load_sweep", "sweep_from_dict", "run_chunk"]
