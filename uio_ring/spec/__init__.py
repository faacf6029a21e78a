"""Spec files (YAML) for the ``uio-ring`` command: loading, validation, design files."""

from uio_ring.spec.designs import design_from_data, design_to_data, load_design, save_design
from uio_ring.spec.loader import (
    DesignSpec,
    OutputSpec,
    SimulateSpec,
    Spec,
    load_spec,
    load_spec_text,
    schema,
    spec_from_dict,
)

__all__ = [
    "DesignSpec",
    "OutputSpec",
    "SimulateSpec",
    "Spec",
    "design_from_data",
    "design_to_data",
    "load_design",
    "load_spec",
    "load_spec_text",
    "save_design",
    "schema",
    "spec_from_dict",
]
