"""Fixtures of the numeric tests: small stand-in systems and the example of paper 001 §5."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest


class ArraySystem:
    """A duck-typed delay system from float coefficient stacks ``(deg + 1, rows, cols)``.

    Tests the simulator against the documented interface (``A … F``, ``h``) without
    going through the exact layer.
    """

    def __init__(self, A, C, B=None, D=None, h=None):
        self.A = np.asarray(A, dtype=float)
        self.C = np.asarray(C, dtype=float)
        n_x, n_y = self.A.shape[1], self.C.shape[1]
        self.B = np.zeros((0, n_x, 0)) if B is None else np.asarray(B, dtype=float)
        n_w = self.B.shape[2]
        self.D = np.zeros((0, n_y, n_w)) if D is None else np.asarray(D, dtype=float)
        self.E = self.F = None
        self.h = h
        self.state_names = None
        self.output_names = None


@pytest.fixture
def scalar_dde():
    """``x' = a x(t) + b x(t − h)``, ``y = x`` with a = −1/2, b = −3/2."""
    return ArraySystem(A=[[[-0.5]], [[-1.5]]], C=[[[1.0]]])


PAPER = dict(
    A="[[0,-1,1,0],[-1,d,0,0],[1,0,1,0],[d,1,1,-1]]",
    B="[[0,0],[0,0],[1,1],[0,d]]",
    C="[[d,0,0,0],[0,1,0,0],[0,0,1,1]]",
    D="[[1,d],[0,0],[1,d]]",
)


def paper_w(t):
    """The unknown inputs of §5: w1 = −10 sin(100 t), w2 = 20 sin(20 t)."""
    t = np.asarray(t, dtype=float)
    return np.array([-10.0 * np.sin(100.0 * t), 20.0 * np.sin(20.0 * t)])


def paper_phi(t):
    """A non-constant initial history (so that the start of the record carries information)."""
    t = np.asarray(t, dtype=float)
    return np.array([np.cos(t), 1.0 + 0 * t, np.sin(3 * t), 0.5 + 0 * t])


@pytest.fixture(scope="session")
def paper_system():
    from uio_ring import DelaySystem

    return DelaySystem(PAPER["A"], PAPER["B"], PAPER["C"], PAPER["D"])


@pytest.fixture(scope="session")
def paper_design(paper_system):
    """The design of ``design_zheng_bejarano`` with the paper's poles (−10, −25, −50)."""
    from uio_ring import design_zheng_bejarano

    return design_zheng_bejarano(paper_system, poles=[-10, -25, -50])


@pytest.fixture(scope="session")
def printed_design(paper_system):
    """The paper's own L0, H, Λ, T, T_L⁻¹ (lag 4) with J corrected (the printed J fails Theorem 4's identity).

    Test data only: J(5,3) = 1 − 2δ and J(6,3) = 0 instead of the printed −1 and 1.
    """
    from uio_ring import PolyMatrix as P

    d = SimpleNamespace(
        system=paper_system,
        L0=P("[[-85,0,1,0,0,0],[0,-85,0,1,0,0],[-2000,0,0,0,1,0],[0,-2000,0,0,0,1],"
             "[-12500,0,0,0,0,0],[0,-12500,0,0,0,0]]"),
        H=P("[[0,0,0],[0,1,-1],[0,0,0],[0,1,-1],[0,d-1,1-d],[0,1,-1]]"),
        J=P("[[83+5*d-d**2,0,0],[0,0,0],[2001-5*d**2+3*d+d**3,d-1,1-d],[0,0,0],"
            "[12503-4*d-d**2+d**3,d-1,1-2*d],[0,0,0]]"),
        Lam=P("[[0,1,0],[0,0,1],[1,0,0]]"),
        T=P("[[0,1,0,0],[-d,0,1,1],[-1,2-4*d+d**2,0,0],[-d,0,1,1],[-2+4*d-d**2,-d+d**2,-1,0],[-d,0,1,1]]"),
        T_left_inverse=P(
            "[[2-4*d+d**2,0,-1,0,0,0],[1,0,0,0,0,0],"
            "[-19*d**2+15*d+8*d**3-4-d**4,0,-4*d+2+d**2,0,-1,0],"
            "[15*d**2-13*d-7*d**3+4+d**4,0,3*d-2-d**2,1,1,0]]"
        ),
        n_z=6,
        lag=4,
    )
    from uio_ring.design.delay_uio_design import guard_blocks_for
    from uio_ring.numeric.build import model_from_exact

    d.numeric = lambda h=None: model_from_exact(
        F=d.L0, G_y=d.J @ d.Lam, D_y=d.H @ d.Lam, X=d.T_left_inverse, initial=d.T.eval(1), h=h,
        guard_blocks=guard_blocks_for(paper_system), z_of_x=d.T, method="printed",
    )
    return d
