"""The noise kernel of an observer whose ``F`` is ``S ⊗ I_r`` (the Zheng–Bejarano ``L0``
without coupling) is stepped with ``e^{S t}`` on the reshaped state: the same kernel and
figures as stepping ``e^{F t}`` itself."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import uio_ring.numeric.performance as pf
from uio_ring.design.methods import design_auto
from uio_ring.spec import load_spec

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_factor_reproduces_F():
    rng = np.random.default_rng(3)
    S = rng.normal(size=(4, 4))
    for r in (1, 2, 5):
        F = np.kron(S, np.eye(r))
        T, q = pf._kron_identity_factor(F)
        assert q % r == 0 and np.array_equal(np.kron(T, np.eye(q)), F)
    F = np.kron(S, np.eye(3))
    F[1, 0] = 0.5  # breaks the structure
    assert pf._kron_identity_factor(F)[1] == 1


@pytest.mark.parametrize("name", ["zheng2015.yaml", "zheng2015_h01.yaml", "two_masses_delay_free.yaml"])
def test_structured_kernel_equals_the_plain_one(name, monkeypatch):
    spec = load_spec(EXAMPLES / name)
    model = design_auto(spec.system, **spec.design.options).design.numeric()
    step = (model.h or 0.01) / 8
    t, K = pf.noise_kernel(model, step, 2.0)
    fast = pf.performance(model)
    monkeypatch.setattr(pf, "_kron_identity_factor", lambda F: (F, 1))
    t0, K0 = pf.noise_kernel(model, step, 2.0)
    slow = pf.performance(model)
    assert np.allclose(K, K0, rtol=1e-10, atol=1e-12 * np.abs(K0).max())
    assert np.allclose(fast.peak_to_peak, slow.peak_to_peak, rtol=1e-9)


def test_zheng_bejarano_L0_has_the_structure():
    spec = load_spec(EXAMPLES / "zheng2015.yaml")
    design = design_auto(spec.system, **spec.design.options).design
    assert design.r > 1
    assert pf._kron_identity_factor(design.numeric().F)[1] % design.r == 0
