"""The float layer: observer models, their discrete steppers and the compiled step loops.

Numpy and scipy only (numba optionally, for the compiled loops); no exact design objects and
no simulation driver — ``design.numeric()`` builds an
:class:`~uio_ring.numeric.model.ObserverModel`, :mod:`uio_ring.sim` steps it.
"""
