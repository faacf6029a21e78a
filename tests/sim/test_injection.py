"""Injection terms whose measured signal is built from other observer states (sigma_xi): two
first-order robust exact differentiators in cascade, the second fed by the first's output —
the structure of a hierarchical super-twisting observer."""

from __future__ import annotations

import numpy as np
import pytest

from uio_ring.errors import SimulationError
from uio_ring.numeric.model import LevantInjection, ObserverModel


def cascade(discretisation="implicit", order_ok=True):
    # ξ = [ζ1, z1, ζ2, z2]: ζ1' = z1 + λ⌈σ1⌋^½, z1' = α sign σ1, σ1 = y − ζ1;
    #                        ζ2' = z2 + λ⌈σ2⌋^½, z2' = α sign σ2, σ2 = z1 − ζ2
    F = np.zeros((4, 4))
    F[0, 1] = F[2, 3] = 1.0
    sigma_xi = np.zeros((2, 4))
    sigma_xi[1, 1] = 1.0  # σ2 reads z1, a state of the earlier chain
    starts = (0, 2)
    if not order_ok:  # chain 1 reading chain 2's state: not solvable in order
        sigma_xi = np.zeros((2, 4))
        sigma_xi[0, 3] = 1.0
    inj = LevantInjection(starts=starts, lengths=(2, 2), gains=((6.0, 8.0), (12.0, 30.0)),
                          sigma_y=np.array([[1.0], [0.0]]), sigma_u=np.zeros((2, 0)),
                          discretisation=discretisation, sigma_xi=sigma_xi)
    X = np.eye(4)[None]
    return ObserverModel(F=F, G_y=np.zeros((1, 4, 1)), X=X, injection=inj, interpolation="linear")


def _errors(disc: str, dt: float, t_final: float = 3.0) -> tuple[float, float]:
    t = np.arange(0, t_final + dt / 2, dt)
    traj = cascade(disc).stepper(dt).trajectories(np.sin(t)[None, :])
    late = t >= 2.0
    return (float(np.abs(traj.x_hat[1] - np.cos(t))[late].max()),
            float(np.abs(traj.x_hat[3] + np.sin(t))[late].max()))


def test_cascade_recovers_first_and_second_derivative():
    """Implicit (set-valued, right-endpoint) steps: both levels exact up to O(dt) — measured
    e1 = 4.5e-5, e2 = 9.9e-5 at dt = 1e-4, halving with dt.  The explicit step chatters and
    the second level, fed by the first's chattering output, is far worse (0.2)."""
    e1, e2 = _errors("implicit", 1e-4)
    assert e1 < 1e-3 and e2 < 1e-3, (e1, e2)
    _, e2_half = _errors("implicit", 5e-5)
    assert e2_half <= 0.6 * e2  # first order in dt
    ex1, ex2 = _errors("explicit", 1e-4)
    assert ex1 < 1e-2 and ex2 > 10 * e2


def test_streaming_equals_the_record():
    dt = 1e-3
    t = np.arange(0, 1.0 + dt / 2, dt)
    y = np.sin(3 * t)[None, :]
    st = cascade().stepper(dt)
    run = st.run(y)
    online = [st.start(y[:, 0])] + [st.step(y[:, k]) for k in range(1, t.size)]
    assert np.allclose(np.array(online).T, run, rtol=1e-12, atol=1e-12)


def _one_step_at_a_time(inj, Phi, Fq, Meas, xi0):
    Xi = [xi0]
    for k in range(1, Meas.shape[0]):
        Xi.append(inj.implicit(Phi @ Xi[-1] + Fq[k - 1], Meas[k]))
    return np.array(Xi)


@pytest.mark.parametrize("case", ["cascade", "example1"])
def test_record_loop_is_the_one_step_map(case):
    """``implicit_run`` (the record's loop, no per-step allocations) takes exactly the steps
    of ``implicit`` — the same floating-point numbers, not just close ones — on the two-chain
    cascade and on the 31-state observer of paper 002's Example 1 (two layers of chains),
    with arguments that slide and that do not."""
    if case == "cascade":
        st = cascade().stepper(1e-3)
    else:
        from design import paper002

        from uio_ring.design.hierarchical_sta import design_hierarchical_sta

        st = design_hierarchical_sta(paper002.example1(), gains=paper002.GAINS).numeric().stepper(1e-3)
    inj, n = st.inj, st.n_z
    rng = np.random.default_rng(11)
    T = 3000
    Fq = 1e-3 * np.cumsum(rng.normal(size=(T, n)), axis=0)
    Meas = np.cumsum(rng.normal(size=(T, len(inj.starts))), axis=0) * 1e-2
    Xi = np.empty((T, n))
    Xi[0] = rng.normal(size=n)
    for k0 in (1, 1000, 2000):  # in pieces, as the record's loop does between checkpoints
        inj.implicit_run(st.Phi, Fq, Meas, Xi, k0, min(k0 + 1000, T) if k0 > 1 else 1000)
    assert np.array_equal(Xi, _one_step_at_a_time(inj, st.Phi, Fq, Meas, Xi[0]))


def test_chains_must_read_earlier_chains_only():
    with pytest.raises(SimulationError, match="later chain 2"):
        cascade(order_ok=False).stepper(1e-3)


def test_implicit_step_solves_the_inclusion_of_every_chain():
    """The closed-form step of the super-twisting chains against the inclusion itself: with
    ``l`` returned, each chain's σ at the new time, ``σ = meas + R (lin + Kl l)``, and its terms
    satisfy ``l_top = κ1 ⌈σ⌋^½`` and ``l_sign ∈ κ2 Sign(σ)`` (the set-valued sign: any value of
    [−κ2, κ2] when σ = 0) — for arguments that slide and that do not."""
    rng = np.random.default_rng(5)
    st = cascade().stepper(1e-2)
    inj = st.inj
    for scale in (1e-4, 1e-2, 1.0, 50.0):
        for _ in range(20):
            lin, meas = rng.normal(size=4) * scale, rng.normal(size=2) * scale
            l = np.linalg.solve(inj.Kl, inj.implicit(lin, meas) - lin)
            sigma = meas + inj.R @ (lin + inj.Kl @ l)
            for j, s in enumerate(inj.starts):
                (k1, k2), sg = inj.kap[j], sigma[j]
                assert abs(l[s] ** 2 - k1**2 * abs(sg)) <= 1e-9 * k1**2 * max(1, scale)  # |l_top| = κ1 |σ|^½
                assert l[s] * sg >= 0 or abs(l[s]) < 1e-6
                if abs(sg) > 1e-9 * max(1, scale):
                    assert l[s + 1] == pytest.approx(k2 * np.sign(sg), abs=1e-9)
                else:
                    assert abs(l[s + 1]) <= k2 * (1 + 1e-12)
