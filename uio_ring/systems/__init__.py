"""Systems layer: :class:`DelaySystem` and its constructors and conversions."""

from uio_ring.systems.delay_system import DelaySystem, delay_system

__all__ = ["DelaySystem", "delay_system"]
