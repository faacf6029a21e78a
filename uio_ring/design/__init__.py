"""Design layer: one module per method; each returns an :class:`ObserverDesign`."""

from uio_ring.design.base import ObserverDesign
from uio_ring.design.high_gain import HighGainDesign, design_high_gain
from uio_ring.design.normal_form import NormalFormDesign, design_normal_form
from uio_ring.design.red_gains import levant_gains
from uio_ring.design.zheng_bejarano import (
    DelayUIODesign,
    design_zheng_bejarano,
    zheng_bejarano_from_choices,
)

__all__ = [
    "DelayUIODesign",
    "ObserverDesign",
    "design_zheng_bejarano",
    "zheng_bejarano_from_choices",
    "NormalFormDesign",
    "design_normal_form",
    "levant_gains",
    "HighGainDesign",
    "design_high_gain",
]
