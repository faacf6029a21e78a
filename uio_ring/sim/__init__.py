"""Numeric backend (float64 only): the plant integrator and the one simulation engine.

>>> from uio_ring.sim import simulate, simulate_observer, HistoryBuffer
"""

from uio_ring.numeric.history import HistoryBuffer
from uio_ring.sim.accuracy import AccuracyCheck, AccuracyWarning
from uio_ring.sim.engine import simulate_observer
from uio_ring.sim.errors import NotSupportedError, SimulationError
from uio_ring.sim.plant import simulate
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import UniformNoise

__all__ = [
    "AccuracyCheck",
    "AccuracyWarning",
    "simulate",
    "simulate_observer",
    "HistoryBuffer",
    "SimulationResult",
    "UniformNoise",
    "SimulationError",
    "NotSupportedError",
]
