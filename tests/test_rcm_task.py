"""The RCM task of any serial arm: both formulations, their Jacobians, the QP and pink steps."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from rcm_pin.control.rcm_loop import position, track
from rcm_pin.control.rcm_qp import RcmQP, chain_model
from rcm_pin.control.rcm_task import (
    constrained_tip_jacobian,
    line_distance,
    make_tool,
    rcm_point,
    rcm_state,
    update_kinematics,
)
from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.studies.surgical_paths import Cone, surgical_path

EXACT = 1e-12
#: Central differences with step 1e-6: truncation ~1e-12 · |third derivative|, round-off
#: ~1e-16 / 1e-6 = 1e-10 per entry; 1e-8 leaves a margin of 100 on the round-off.
FD = 1e-8
ARMS = {"panda": "panda_hand_tcp", "ur5": "tool0"}


@pytest.fixture(scope="module", params=sorted(ARMS))
def arm(request):
    """(mechanism, chain model, a random configuration, a trocar 5 mm off the shaft)."""
    mech = rcm_pin.load(request.param)
    home = mech.home
    chain = chain_model(mech, ARMS[request.param], "z", 0.3, (0.0, 0.0, 0.0), home)
    rng = np.random.default_rng(7)
    m = chain.model
    q = home[chain.active] + rng.uniform(-0.3, 0.3, m.nq)
    q = np.clip(q, m.lowerPositionLimit, m.upperPositionLimit)
    data = m.createData()
    update_kinematics(m, data, q)
    s = rcm_state(m, data, chain.tool)
    side = np.cross(s.axis, [1.0, 0.0, 0.0])
    trocar = s.p_shaft + 0.17 * s.axis + 0.005 * side / np.linalg.norm(side)
    return mech, chain, q, trocar


def _state(model, tool, q):
    data = model.createData()
    update_kinematics(model, data, q)
    return rcm_state(model, data, tool)


def _central(f, x, h=1e-6):
    cols = []
    for i in range(len(x)):
        dx = np.zeros(len(x))
        dx[i] = h
        cols.append((f(x + dx) - f(x - dx)) / (2 * h))
    return np.column_stack(cols)


def test_jacobians_match_finite_differences(arm):
    _, chain, q, trocar = arm
    m, tool = chain.model, chain.tool.with_trocar(trocar)
    s = _state(m, tool, q)
    np.testing.assert_allclose(s.J_tip, _central(lambda x: _state(m, tool, x).p_tip, q), atol=FD)
    np.testing.assert_allclose(s.J_dist, _central(lambda x: _state(m, tool, x).e, q), atol=FD)
    data = m.createData()

    def p_rcm(x):  # λ is the last variable
        return rcm_point(m, data, tool, x[:-1], x[-1])

    np.testing.assert_allclose(s.J_lam, _central(p_rcm, np.append(q, s.lam)), atol=FD)


def test_the_two_formulations_agree(arm):
    _, chain, q, trocar = arm
    tool = chain.tool.with_trocar(trocar)
    s = _state(chain.model, tool, q)
    assert s.distance > 4e-3  # the trocar is off the shaft: a non-trivial check
    # the same point and distance by three routes
    np.testing.assert_allclose(s.distance, line_distance(s.p_shaft, s.axis, trocar), atol=EXACT)
    np.testing.assert_allclose(s.distance, np.linalg.norm(trocar - s.p_rcm), atol=EXACT)
    np.testing.assert_allclose(s.axis @ (trocar - s.p_rcm), 0.0, atol=EXACT)
    # b_iᵀ J_λ,q at λ* = −∂e_i/∂q + (b_i × e⊥)ᵀ J_ω; the λ column lies along the axis
    data = chain.model.createData()
    update_kinematics(chain.model, data, q)
    B = data.oMf[tool.axis_frame].rotation[:, :2]  # the z axis is the shaft
    Jw = pin.getFrameJacobian(chain.model, data, tool.axis_frame, pin.LOCAL_WORLD_ALIGNED)[3:]
    e_perp = trocar - s.p_rcm
    extra = np.vstack([np.cross(B[:, i], e_perp) @ Jw for i in range(2)])
    np.testing.assert_allclose(B.T @ s.J_lam[:, :-1], -s.J_dist + extra, atol=EXACT)
    np.testing.assert_allclose(B.T @ s.J_lam[:, -1], 0.0, atol=EXACT)
    assert np.abs(extra).max() > 1e-3  # off the shaft the two differ: the identity has content


@pytest.mark.parametrize("formulation", ["distance", "lambda"])
def test_each_formulation_drives_the_distance_to_zero(arm, formulation):
    _, chain, q, trocar = arm
    tool = chain.tool.with_trocar(trocar)
    ctrl = RcmQP(chain.model, tool, 1e-3, formulation=formulation)
    start = ctrl.state(q)
    x = q.copy()
    history = [start.distance]
    for _ in range(6):  # hard steps with the tip held; dt = 50 ms: the box admits 5 mm
        x = x + ctrl.step(x, start.p_tip, dt=0.05)
        history.append(ctrl.state(x).distance)
    assert history[0] > 4e-3
    assert history[-1] < EXACT
    assert all(history[k + 1] < 0.1 * history[k] for k in range(3))  # Newton-like decay


def test_one_step_is_the_same_by_both_formulations_and_pink(arm):
    _, chain, q, trocar = arm
    ctrl = RcmQP(chain.model, chain.tool.with_trocar(trocar), 1e-3)
    target = ctrl.state(q).p_tip
    q0 = position(ctrl, q, target)  # RCM exact, tip at target
    move = target + np.array([1e-5, -2e-5, 1e-5])  # 25 µm in 1 ms: 25 mm/s
    dq = ctrl.step(q0, move)
    ctrl_lam = RcmQP(chain.model, chain.tool.with_trocar(trocar), 1e-3, formulation="lambda")
    # At e = 0 the constraint rows coincide; the QPs differ only by e ~ 1e-12 terms.
    np.testing.assert_allclose(ctrl_lam.step(q0, move), dq, atol=1e-10)
    np.testing.assert_allclose(ctrl.step_pink(q0, move), dq, atol=1e-10)
    s = ctrl.state(q0 + dq)
    # one linearised step leaves the second-order remainder |Δq|² |∂²p/∂q²| ≈ (1e-4)² 0.5 m
    bound = 0.5 * float(dq @ dq)
    assert s.distance < bound and np.linalg.norm(s.p_tip - move) < bound


def test_control_rate_run_meets_the_goals_and_the_velocity_limits(arm):
    mech, chain, q, _ = arm
    ctrl0 = RcmQP(chain.model, chain.tool, 1e-3)
    s0 = ctrl0.state(q)
    cone = Cone(tuple(s0.p_shaft + 0.2 * s0.axis), tuple(s0.axis))
    path = surgical_path("circle", cone, duration=0.1)
    ctrl = RcmQP(chain.model, chain.tool.with_trocar(cone.apex), 1e-3)
    q0 = position(ctrl, q, path.p[0])
    run = track(ctrl, q0, path.p)
    assert run.rcm_error.max() <= 1e-6 and run.tip_error.max() <= 1e-4
    v = np.diff(run.q, axis=0) / 1e-3
    assert np.all(np.abs(v) <= chain.model.velocityLimit * (1 + 1e-9))
    # independent route: Pinocchio FK of the full mechanism, the line distance
    data = mech.model.createData()
    for k in (0, len(run.q) // 2, len(run.q) - 1):
        pin.framesForwardKinematics(mech.model, data, mech.to_pin(chain.to_mechanism(run.q[k])))
        M = data.oMf[mech.model.getFrameId(ARMS[mech.name])]
        d = line_distance(M.translation, M.rotation[:, 2], np.asarray(cone.apex))
        np.testing.assert_allclose(d, run.rcm_error[k], atol=EXACT)


def test_constrained_tip_jacobian_keeps_the_rcm(arm):
    _, chain, q, trocar = arm
    s = _state(chain.model, chain.tool.with_trocar(trocar), q)
    Jc = constrained_tip_jacobian(s)
    assert Jc.shape == (3, chain.model.nv - 2)
    _, sv, vt = np.linalg.svd(s.J_dist)
    N = vt[2:].T
    np.testing.assert_allclose(s.J_dist @ N, 0.0, atol=EXACT)
    np.testing.assert_allclose(Jc @ Jc.T, s.J_tip @ N @ N.T @ s.J_tip.T, atol=EXACT)


def test_errors_are_typed_with_exact_messages():
    ur5 = rcm_pin.load("ur5")
    with pytest.raises(UnknownFrameError) as err:
        make_tool(ur5.model, "shaft")
    frames = ", ".join(sorted({f.name for f in ur5.model.frames}))
    assert str(err.value) == f"unknown tool frame 'shaft' in ur5; valid: {frames}"
    assert frames.startswith("base, base_link, base_link-base_fixed_joint")
    with pytest.raises(InvalidInputError, match=r"^tool axis must be one of x, y, z; got 'w'$"):
        make_tool(ur5.model, "tool0", "w")
    with pytest.raises(InvalidInputError, match=r"^trocar must be 3 finite numbers x,y,z \[m\]"):
        make_tool(ur5.model, "tool0", trocar=(0.0, np.nan, 0.0))
    tool = make_tool(ur5.model, "tool0")
    with pytest.raises(InvalidInputError) as err:
        RcmQP(ur5.model, tool, 1e-3, formulation="drake")
    assert str(err.value) == "formulation must be 'distance' or 'lambda'; got 'drake'"


def test_pink_tasks_report_the_rcm_geometry(arm):
    import pink

    from rcm_pin.control.rcm_pink import RcmTask, ToolTipTask

    _, chain, q, trocar = arm
    tool = chain.tool.with_trocar(trocar)
    conf = pink.Configuration(chain.model, chain.model.createData(), q)
    s = _state(chain.model, tool, q)
    rcm, tip = RcmTask(tool), ToolTipTask(tool)
    tip.set_target(s.p_tip + 0.01)
    np.testing.assert_allclose(rcm.compute_error(conf), s.e, atol=EXACT)
    np.testing.assert_allclose(rcm.compute_jacobian(conf), s.J_dist, atol=EXACT)
    np.testing.assert_allclose(tip.compute_error(conf), -0.01 * np.ones(3), atol=EXACT)
    np.testing.assert_allclose(tip.compute_jacobian(conf), s.J_tip, atol=EXACT)


def test_both_formulations_follow_the_same_trajectory(arm):
    _, chain, q, _ = arm
    ctrl = RcmQP(chain.model, chain.tool, 1e-3)
    s0 = ctrl.state(q)
    cone = Cone(tuple(s0.p_shaft + 0.2 * s0.axis), tuple(s0.axis))
    path = surgical_path("spiral", cone, duration=0.05)
    tool = chain.tool.with_trocar(cone.apex)
    q0 = position(RcmQP(chain.model, tool, 1e-3), q, path.p[0])
    runs = []
    for form in ("distance", "lambda"):
        runs.append(track(RcmQP(chain.model, tool, 1e-3, formulation=form), q0, path.p))
    # the constraint rows differ by (b_i × e⊥)ᵀ J_ω with |e⊥| ≤ 1e-9: Δq by ~1e-9 |J|
    np.testing.assert_allclose(runs[0].q, runs[1].q, atol=1e-9)
    assert max(r.rcm_error.max() for r in runs) <= 1e-6
