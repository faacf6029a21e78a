"""Numeric backend (float64 only): history buffers, plant and observer simulation.

>>> from uio_ring.sim import simulate, simulate_observer, HistoryBuffer
"""

from uio_ring.sim.errors import NotSupportedError, SimulationError
from uio_ring.sim.history import HistoryBuffer
from uio_ring.sim.normal_form_observer import NormalFormObserver, simulate_normal_form_observer
from uio_ring.sim.observer import DelayObserverSimulator, simulate_observer
from uio_ring.sim.plant import simulate
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import UniformNoise

__all__ = [
    "simulate",
    "simulate_observer",
    "DelayObserverSimulator",
    "HistoryBuffer",
    "SimulationResult",
    "UniformNoise",
    "SimulationError",
    "NotSupportedError",
    "NormalFormObserver",
    "simulate_normal_form_observer",
]
