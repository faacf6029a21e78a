"""The one least-noise search (uio_ring.design.noise) on every method whose linear part has
free poles: the G0 coupling keeps the spectrum exactly (any strictly triangular part, not
others), the searched poles respect the rate, and the options are read from specs."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring import DelaySystem, design_zheng_bejarano
from uio_ring.design import zheng_bejarano as zb
from uio_ring.design.hierarchical_sta import design_hierarchical_sta
from uio_ring.design.high_gain import design_high_gain
from uio_ring.design.methods import get_method
from uio_ring.design.noise import pole_patterns
from uio_ring.errors import DomainError, SpecError
from uio_ring.ring.matrix import PolyMatrix

#: three integrators seen at both ends: r = 2, l* = 2 (four coupling slots per triangle)
CHAIN = DelaySystem("[[0, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[1, 0, 0], [0, 0, 1]]", None)


def _rebuild(base, extra):
    s12 = zb._Step12(base.U, base.V, base.Vbar, base.W, base.A_bar, base.C_tilde)
    return zb._assemble(base.system, s12, base.Lam, F_stack=base.F_stack, O_left_inverse=base.O_left_inverse,
                        T_left_inverse=base.T_left_inverse, poles=base.poles, G0_extra=extra)


small = st.fractions(min_value=-20, max_value=20, max_denominator=7)


@settings(max_examples=15, deadline=None)
@given(st.lists(small, min_size=2, max_size=2), st.booleans(), small.filter(lambda v: v != 0))
def test_a_triangular_coupling_keeps_the_spectrum_and_others_do_not(vals, upper, stray):
    """det(sI − L0) = Π(s − p)^r for G0 + any strictly block-triangular part (the certificate
    checks it exactly); one entry on both sides of the diagonal breaks it in general."""
    base = design_zheng_bejarano(CHAIN, poles=[-2, -3])
    r, l = base.r, base.l_star
    assert (r, l) == (2, 2)
    i, j = (0, 1) if upper else (1, 0)
    rows = [[Fraction(0)] * r for _ in range(r * l)]
    for k in range(l):
        rows[k * r + i][j] = vals[k]
    d = _rebuild(base, PolyMatrix(rows, shape=(r * l, r)))
    assert d.certificate().ok
    if vals[1] != 0:  # the block k = 1 coupling (constant term of the channel polynomials' product)
        rows[r + j][i] = stray  # the other side too: a full 2×2 block, its determinant moves
        broken = _rebuild(base, PolyMatrix(rows, shape=(r * l, r)))
        failed = [c.name for c in broken.certificate().checks if not c.ok]
        assert failed == ["spectrum of A0 − G0 C0"], failed


def test_sta_min_noise_searches_the_luenberger_poles():
    sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None)
    d = design_hierarchical_sta(sys, poles="min-noise", rate=3)
    perf = d.performance()
    assert "Luenberger stage" in perf.scope and perf.summary().startswith("Luenberger stage")
    assert perf.decay_rate >= 3 * (1 - 1e-6)
    others = [design_hierarchical_sta(sys, poles=p).performance().noise_gain.max() for p in pole_patterns(2, Fraction(3))]
    assert perf.noise_gain.max() == pytest.approx(min(others), rel=1e-3)
    assert d.certificate().ok
    with pytest.raises(DomainError, match="apply to poles='min-noise' only"):
        design_hierarchical_sta(sys, poles=[-1, -2], rate=3)
    with pytest.raises(DomainError, match="K or poles"):
        design_hierarchical_sta(sys, poles="min-noise", K=[[1], [1]])


def test_high_gain_min_noise_respects_the_rate_at_any_epsilon():
    A = "[[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]"
    W1 = [[0, -1, 0, 1, 0], [0, 0, 0, 0, 1], [0, -1, 0, 1, 0], [1, 0, 0, 0, 1], [0, 1, 0, 0, 0]]
    sys = DelaySystem(A, [[0]] * 5, "[[1,0,0,0,0],[0,0,1,0,0]]", None)
    gains = []
    for eps in (1, "3/10"):
        d = design_high_gain(sys, W=[W1], poles="min-noise", rate=2, epsilon=eps)
        perf = d.performance()
        assert perf.decay_rate >= 2 * (1 - 1e-4)  # a triple pole: its float eigenvalues spread by ~1e-5
        assert d.certificate().ok
        gains.append(perf.noise_gain)
    assert np.allclose(gains[0], gains[1], rtol=1e-6)  # the same error poles: the same observer
    with pytest.raises(DomainError, match="poles or coefficients"):
        design_high_gain(sys, W=[W1], poles="min-noise", coefficients=[[1, 2, 3]])


def test_normal_form_has_no_free_poles():
    assert "poles" not in get_method("normal-form").option_names
    assert "no free poles" in " ".join(o.doc for o in get_method("normal-form").options)


def test_spec_options():
    for name in ("zheng-bejarano", "hierarchical-sta", "high-gain"):
        m = get_method(name)
        opts = m.read_options({"poles": "min-noise", "rate": 4, "criterion": "h2"})
        assert opts == {"poles": "min-noise", "rate": Fraction(4), "criterion": "h2"}
        with pytest.raises(SpecError) as exc:
            m.read_options({"criterion": "hinf"})
        assert exc.value.path == "design.criterion"
