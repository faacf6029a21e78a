"""Design layer: one module per method; each returns an :class:`ObserverDesign`."""

from uio_ring.design.base import ObserverDesign
from uio_ring.design.zheng_bejarano import (
    DelayUIODesign,
    design_zheng_bejarano,
    zheng_bejarano_from_choices,
)

__all__ = ["DelayUIODesign", "ObserverDesign", "design_zheng_bejarano", "zheng_bejarano_from_choices"]
