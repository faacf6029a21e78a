"""uio_ring — exact design and verification of unknown-input observers for
linear systems with commensurate delays.

The public names are importable from here; they are loaded lazily, so that
``import uio_ring`` stays cheap (no sympy, flint, numpy or matplotlib until a
name that needs them is used).

>>> from uio_ring import PolyMatrix, smith
>>> smith(PolyMatrix("[[d, 0], [0, d + 1]]")).invariant_factors
(1, d**2 + d)
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

# name -> module that defines it.  Add one line per public name.
_LAZY: dict[str, str] = {
    # ring (issue 2)
    "PolyMatrix": "uio_ring.ring.matrix",
    "Poly": "uio_ring.ring.poly",
    "QMatrix": "uio_ring.ring.qmatrix",
    "hermite": "uio_ring.ring.hermite",
    "HermiteResult": "uio_ring.ring.hermite",
    "is_hermite": "uio_ring.ring.hermite",
    "smith": "uio_ring.ring.smith",
    "SmithResult": "uio_ring.ring.smith",
    "invariant_factors": "uio_ring.ring.smith",
    "is_smith": "uio_ring.ring.smith",
    "left_inverse": "uio_ring.ring.inverse",
    "right_inverse": "uio_ring.ring.inverse",
    "is_unimodular": "uio_ring.ring.inverse",
    "is_left_unimodular": "uio_ring.ring.inverse",
    "is_right_unimodular": "uio_ring.ring.inverse",
    "left_kernel": "uio_ring.ring.kernel",
    "solve_left": "uio_ring.ring.solve",
    "solve_right": "uio_ring.ring.solve",
    "right_kernel": "uio_ring.ring.kernel",
    "Certificate": "uio_ring.ring.certificate",
    "Check": "uio_ring.ring.certificate",
    # errors
    "UioRingError": "uio_ring.errors",
    "DimensionError": "uio_ring.errors",
    "ParseError": "uio_ring.errors",
    "DomainError": "uio_ring.errors",
    "NotUnimodularError": "uio_ring.errors",
    "NoPolynomialSolutionError": "uio_ring.errors",
    "MissingDependencyError": "uio_ring.errors",
    "NotObservableError": "uio_ring.errors",
    "SpecError": "uio_ring.errors",
    # numerics (issue 4): float64 simulation
    "simulate": "uio_ring.sim.plant",
    "simulate_observer": "uio_ring.sim.engine",
    "simulate_batch": "uio_ring.sim.batch",
    "Scenario": "uio_ring.sim.batch",
    "BatchResult": "uio_ring.sim.batch",
    "sweep": "uio_ring.sweeps.runner",
    "load_sweep": "uio_ring.sweeps.spec",
    "SimulationResult": "uio_ring.sim.result",
    "ObserverModel": "uio_ring.numeric.model",
    # spec files and design files (issue 5)
    "load_spec": "uio_ring.spec.loader",
    "load_design": "uio_ring.spec.designs",
    "save_design": "uio_ring.spec.designs",
    "design_auto": "uio_ring.design.methods",
    # systems / analysis / design (issue 3) — add entries here
    "DelaySystem": "uio_ring.systems.delay_system",
    "delay_system": "uio_ring.systems.delay_system",
    "unknown_input_observability": "uio_ring.analysis.observability",
    "check_rank_condition": "uio_ring.analysis.rank_condition",
    "check_assumptions": "uio_ring.analysis.assumptions",
    "ObservabilityReport": "uio_ring.analysis.report",
    "RankConditionReport": "uio_ring.analysis.report",
    "AssumptionsReport": "uio_ring.analysis.report",
    "ObserverDesign": "uio_ring.design.base",
    "DelayUIODesign": "uio_ring.design.zheng_bejarano",
    "design_zheng_bejarano": "uio_ring.design.zheng_bejarano",
    "zheng_bejarano_from_choices": "uio_ring.design.zheng_bejarano",
    "delay_uio_certificate": "uio_ring.verify.delay_uio",
    # delay-free methods I (issue 6): strong observability, observer normal form (Niederwieser et al. 2022)
    "rosenbrock_matrix": "uio_ring.analysis.strong_observability",
    "invariant_zeros": "uio_ring.analysis.strong_observability",
    "InvariantZeros": "uio_ring.analysis.strong_observability",
    "is_strongly_observable": "uio_ring.analysis.strong_observability",
    "is_strongly_detectable": "uio_ring.analysis.strong_observability",
    "is_strong_star_detectable": "uio_ring.analysis.strong_observability",
    "StrongObservabilityReport": "uio_ring.analysis.strong_observability",
    "weakly_unobservable_subspace": "uio_ring.analysis.strong_observability",
    "relative_degrees": "uio_ring.analysis.infinite_structure",
    "observability_indices": "uio_ring.analysis.infinite_structure",
    "infinite_zero_structure": "uio_ring.analysis.infinite_structure",
    "normal_form_chain_lengths": "uio_ring.analysis.infinite_structure",
    "normal_form_applicable": "uio_ring.analysis.normal_form_applicability",
    "NormalFormApplicability": "uio_ring.analysis.normal_form_applicability",
    "design_normal_form": "uio_ring.design.normal_form",
    "NormalFormDesign": "uio_ring.design.normal_form",
    "levant_gains": "uio_ring.design.red_gains",
    "normal_form_certificate": "uio_ring.verify.normal_form",
    # delay-free methods IV (issue 12): high-gain observers with output shaping (Grip & Saberi)
    "admissibility": "uio_ring.analysis.admissibility",
    "AdmissibilityReport": "uio_ring.analysis.admissibility",
    "canonical_form": "uio_ring.analysis.canonical_form",
    "CanonicalForm": "uio_ring.analysis.canonical_form",
    "shape": "uio_ring.analysis.output_shaping",
    "ShapingResult": "uio_ring.analysis.output_shaping",
    "high_gain_applicable": "uio_ring.analysis.high_gain_applicability",
    "jacobian_basis": "uio_ring.analysis.jacobian_basis",
    "design_high_gain": "uio_ring.design.high_gain",
    "HighGainDesign": "uio_ring.design.high_gain",
    "high_gain_certificate": "uio_ring.verify.high_gain",
    # delay-free methods II (issue 10): the special coordinate basis (Tranninger et al. 2021)
    "special_coordinate_basis": "uio_ring.analysis.scb",
    "SpecialCoordinateBasis": "uio_ring.analysis.scb",
    "scb_dimensions": "uio_ring.analysis.scb",
    "observer_options": "uio_ring.analysis.observer_classes",
    "ObserverOptions": "uio_ring.analysis.observer_classes",
    "design_scb": "uio_ring.design.scb",
    "SCBDesign": "uio_ring.design.scb",
    "scb_design_certificate": "uio_ring.verify.scb",
}

__all__ = sorted(_LAZY) + ["__version__"]


def __getattr__(name: str) -> Any:
    try:
        module = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'uio_ring' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
