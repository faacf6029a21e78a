"""Which backend runs the step loop of an observer with an injection term: ``"python"`` or ``"numba"``.

The loop over the steps (and over the scenarios of a batch) of a sliding-mode or
differentiator observer is nonlinear, so it runs one step at a time.  It has two
implementations: the Python one (numpy; always there) and a compiled one
(:mod:`uio_ring.numeric.kernel`, needs the optional dependency numba:
``pip install 'uio-ring[fast]'``).  The choice, in this order:

* the keyword ``kernel=`` of :class:`~uio_ring.numeric.stepper.ObserverStepper`
  (and of ``simulate_observer``, ``simulate_batch``);
* else the environment variable ``UIO_RING_KERNEL``;
* else ``"auto"``: numba when it can be imported, else Python.

The same switch selects the compiled linear loops of ``simulate_batch``
(:mod:`uio_ring.numeric.scenario_kernel`: the plant's and a linear observer's taps and
recursions, scenario-innermost; :mod:`uio_ring.numeric.linear_kernel`: other observers' taps,
time-major) and its metrics (:mod:`uio_ring.numeric.metrics_kernel`).  Threads
(``UIO_RING_THREADS``, default 1) run whole chunks of a batch's scenarios
(:func:`uio_ring.sim.batch.chunk_bounds`), with the same numbers for any thread count up to
rounding (the BLAS may round a row of a product by the rows around it).

``"numba"`` asked for explicitly without numba installed is an error naming the extra.
The two backends agree up to rounding (the sliding modes amplify last-bit differences).

>>> resolve_kernel("python")
'python'
>>> resolve_kernel("fortran")
Traceback (most recent call last):
...
uio_ring.errors.SimulationError: kernel='fortran'; expected one of ('auto', 'python', 'numba')
"""

from __future__ import annotations

import importlib
import os

from uio_ring.errors import SimulationError, require

__all__ = ["KERNELS", "KERNEL_ENV", "resolve_kernel"]

#: Values of the ``kernel`` option (and of the environment variable :data:`KERNEL_ENV`).
KERNELS = ("auto", "python", "numba")
#: The environment variable read when no ``kernel`` keyword is given.
KERNEL_ENV = "UIO_RING_KERNEL"


def resolve_kernel(kernel: str | None = None) -> str:
    """``"python"`` or ``"numba"``: the backend that ``kernel`` (None: ``$UIO_RING_KERNEL``, else
    ``"auto"``) selects on this machine.

    Raises
    ------
    SimulationError
        For a value not in :data:`KERNELS`.
    MissingDependencyError
        For ``"numba"`` when numba cannot be imported.
    """
    source = "kernel"
    if kernel is None:
        kernel, source = os.environ.get(KERNEL_ENV, "") or "auto", KERNEL_ENV
    choice = str(kernel).strip().lower()
    if choice not in KERNELS:
        raise SimulationError(f"{source}={kernel!r}; expected one of {KERNELS}")
    if choice == "python":
        return "python"
    if choice == "numba":
        require("numba", extra="fast")
        return "numba"
    try:
        importlib.import_module("numba")
    except ImportError:
        return "python"
    return "numba"
