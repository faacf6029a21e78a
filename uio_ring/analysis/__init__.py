"""Analysis layer: structural properties of delay systems (exact, over Q[δ])."""

from uio_ring.analysis.admissibility import AdmissibilityReport, admissibility
from uio_ring.analysis.assumptions import check_assumptions
from uio_ring.analysis.canonical_form import CanonicalForm, canonical_form, observability_indices_of
from uio_ring.analysis.high_gain_applicability import HighGainApplicability, high_gain_applicable
from uio_ring.analysis.infinite_structure import (
    InfiniteZeroStructure,
    ObservabilityIndices,
    RelativeDegrees,
    infinite_zero_structure,
    normal_form_chain_lengths,
    observability_indices,
    relative_degrees,
)
from uio_ring.analysis.jacobian_basis import JacobianBasis, jacobian_basis
from uio_ring.analysis.normal_form_applicability import (
    NormalFormApplicability,
    normal_form_applicable,
)
from uio_ring.analysis.observability import unknown_input_observability
from uio_ring.analysis.observer_classes import ObserverOptions, observer_options
from uio_ring.analysis.output_shaping import (
    ExtendStep,
    Filter,
    ShapingResult,
    ShapingStep,
    extend,
    extended_set,
    shape,
)
from uio_ring.analysis.rank_condition import check_rank_condition, matching_matrix
from uio_ring.analysis.report import (
    AssumptionsReport,
    ObservabilityReport,
    RankConditionReport,
    Report,
)
from uio_ring.analysis.scb import (
    NotLeftInvertibleError,
    SCBDimensions,
    SpecialCoordinateBasis,
    scb_dimensions,
    special_coordinate_basis,
)
from uio_ring.analysis.strong_observability import (
    InvariantZeros,
    StrongObservabilityReport,
    invariant_zeros,
    is_strong_star_detectable,
    is_strongly_detectable,
    is_strongly_observable,
    rosenbrock_matrix,
    weakly_unobservable_subspace,
)

__all__ = [
    "AssumptionsReport",
    "ObservabilityReport",
    "RankConditionReport",
    "Report",
    "check_assumptions",
    "check_rank_condition",
    "matching_matrix",
    "unknown_input_observability",
    # issue 6
    "InfiniteZeroStructure",
    "InvariantZeros",
    "NormalFormApplicability",
    "ObservabilityIndices",
    "RelativeDegrees",
    "StrongObservabilityReport",
    "infinite_zero_structure",
    "invariant_zeros",
    "is_strong_star_detectable",
    "is_strongly_detectable",
    "is_strongly_observable",
    "normal_form_applicable",
    "normal_form_chain_lengths",
    "observability_indices",
    "relative_degrees",
    "rosenbrock_matrix",
    "weakly_unobservable_subspace",
    # issue 12: high-gain observers with output shaping (Grip & Saberi 2010)
    "AdmissibilityReport",
    "CanonicalForm",
    "ExtendStep",
    "Filter",
    "ShapingResult",
    "ShapingStep",
    "admissibility",
    "canonical_form",
    "extend",
    "extended_set",
    "observability_indices_of",
    "shape",
    "HighGainApplicability",
    "high_gain_applicable",
    "JacobianBasis",
    "jacobian_basis",
    # issue 10: the special coordinate basis and Table 1 (Tranninger et al. 2021)
    "NotLeftInvertibleError",
    "ObserverOptions",
    "SCBDimensions",
    "SpecialCoordinateBasis",
    "observer_options",
    "scb_dimensions",
    "special_coordinate_basis",
]
