"""The kernel's inputs against Pinocchio: ``ocp.closure.log6`` is ``pin.log6`` and
``pinocchio_closure`` is ``rcm_pin.model.loops.residual_and_jacobian`` (residual and Newton
Jacobian on the passive joints) at random configurations, closed or not."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp.closure import log6, pinocchio_closure
from ocp.symbolic import SymbolicModel

#: Exact identities evaluated by two codes (rounding only).
EXACT = 1e-12


def test_log6_is_pinocchios():
    rot, p = ca.SX.sym("R", 3, 3), ca.SX.sym("p", 3)
    fun = ca.Function("log6", [rot, p], [log6(rot, p)])
    rng = np.random.default_rng(4)
    for angle in (2.5, 1.0, 0.1, 1e-3, 1e-5, 1e-9, 0.0):  # down to the series and identity
        # 1e-3 <= θ <= 1e-5: α = θ sin θ / (2 (1 − cos θ)) loses ~eps/θ² to the cancellation
        # in 1 − cos θ, in both codes (Pinocchio's series starts below θ = eps^(1/3), ours
        # below θ = 1e-4), so they agree to eps/θ² there, not to rounding
        tol = EXACT if angle > 0.05 or angle < 1e-8 else max(EXACT, 4e-16 / angle**2)
        for _ in range(5):
            axis = rng.normal(size=3)
            m = pin.SE3(pin.exp3(angle * axis / np.linalg.norm(axis)), rng.normal(size=3))
            got = np.asarray(fun(m.rotation, m.translation)).ravel()
            np.testing.assert_allclose(got, pin.log6(m).vector, rtol=0, atol=tol)


@pytest.mark.parametrize(
    "name", ["planar_3rrr", "spherical_3rrr", "translational_3ppapa", "eye_4dof"]
)
def test_pinocchio_closure_is_pinocchios_residual_and_jacobian(name):
    mech = rcm_pin.load(name)
    loops = mech.loops
    q = ca.SX.sym("q", mech.model.nq)
    e, jp = pinocchio_closure(SymbolicModel(mech.model), loops, q, loops.passive_v.tolist())
    fun = ca.Function("closure", [q], [e, jp])
    rng = np.random.default_rng(8)
    for q0 in rng.uniform(-0.8, 0.8, (10, mech.model.nq)):  # away from closure
        e_pin, j_pin = mech.residual_and_jacobian(q0)
        e_ca, j_ca = (np.asarray(v) for v in fun(q0))
        np.testing.assert_allclose(e_ca.ravel(), e_pin, rtol=0, atol=EXACT)
        np.testing.assert_allclose(j_ca, j_pin[:, loops.passive_v], rtol=0, atol=EXACT)
