"""The programmable RCM in the CasADi layer: IK NLP with the RCM as an equality or a
tolerance, and the tracking OCP with the RCM as a path constraint; errors recomputed by
Pinocchio forward kinematics of the full arm (not the NLP's symbolic twin)."""

from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocp.rcm import TIP_FRAME, RcmIK, tip_model
from ocp.rcm_tracking import RcmTrackingOCP
from rcm_pin.catalog import load
from rcm_pin.control.rcm_loop import track
from rcm_pin.control.rcm_qp import RcmQP
from rcm_pin.control.rcm_task import line_distance, rcm_state, update_kinematics
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.studies.rcm_comparison import make_setup, start_configuration
from rcm_pin.studies.surgical_paths import surgical_path

EXACT = 1e-12
SOLVER = 1e-9


@pytest.fixture(scope="module", params=["panda", "ur5"])
def setup(request):
    return _trocar_setup(request.param)


@functools.cache
def _trocar_setup(name):
    """The arm at a fixed, reachable trocar 0.15 m below its home tool frame."""
    mech = load(name)
    home = mech.home
    data = mech.model.createData()
    pin.framesForwardKinematics(mech.model, data, mech.to_pin(home))
    M = data.oMf[mech.tool_frame_id]
    return make_setup(name, M.translation + 0.15 * M.rotation[:, 2])


def _fk_errors(s, q_chain, target):
    mech = s.mech
    q = mech.to_pin(s.chain.to_mechanism(q_chain))
    data = mech.model.createData()
    pin.framesForwardKinematics(mech.model, data, q)
    M = data.oMf[s.tool.axis_frame]
    a = M.rotation[:, 2]
    rcm = float(line_distance(M.translation, a, np.asarray(s.tool.trocar)))
    return rcm, float(np.linalg.norm(M.translation + s.tool.tip_offset * a - target))


def test_tip_frame_is_the_tool_tip(setup):
    s = setup
    model = tip_model(s.chain.model, s.chain.tool)
    data = model.createData()
    q = s.home[s.chain.active]
    update_kinematics(model, data, q)
    st = rcm_state(model, data, s.chain.tool)
    np.testing.assert_allclose(data.oMf[model.getFrameId(TIP_FRAME)].translation, st.p_tip,
                               atol=EXACT)  # fmt: skip


def test_ik_with_exact_rcm_meets_both_goals(setup):
    s = setup
    ik = RcmIK(s.chain.model, s.chain.tool)
    q = s.home[s.chain.active]
    for p in surgical_path("spiral", s.cone, rate=1.0).p[::2]:  # 4 points from the axis out
        r = ik.solve(p, q)
        assert r.ik.success
        rcm, tip = _fk_errors(s, r.ik.q, p)
        assert rcm <= SOLVER and tip <= SOLVER
        np.testing.assert_allclose([rcm, tip], [r.rcm_error, r.tip_error], atol=EXACT)
        assert np.all(r.ik.q >= s.chain.model.lowerPositionLimit)
        assert np.all(r.ik.q <= s.chain.model.upperPositionLimit)
        q = r.ik.q


def _home_tip(s):
    ik = RcmIK(s.chain.model, s.chain.tool)
    q = s.home[s.chain.active]
    pin.framesForwardKinematics(ik.model, ik.data, q)
    return ik, q, ik.data.oMf[ik.tip_id].translation.copy()


def test_lm_route_meets_both_goals_and_agrees_with_ipopt(setup):
    """Seeded targets within 3 cm of the home tip (reachable: IPOPT's route reaches them
    too): RCM and tip within 1e-9 m by the tests' own FK, joint limits kept, and the
    residuals of the two routes agree (their q differ: 7 joints, 5 equations)."""
    s = setup
    lm, q, tip = _home_tip(s)
    assert lm.solver == "lm"
    ipopt = RcmIK(s.chain.model, s.chain.tool, solver="ipopt")
    rng = np.random.default_rng(27)
    lo, hi = s.chain.model.lowerPositionLimit, s.chain.model.upperPositionLimit
    for _ in range(6):
        d = rng.normal(size=3)
        p = tip + 0.03 * rng.uniform() ** (1 / 3) * d / np.linalg.norm(d)
        a, b = lm.solve(p, q), ipopt.solve(p, q)
        assert a.ik.success and a.ik.solver == "lm" and b.ik.success
        rcm, err = _fk_errors(s, a.ik.q, p)
        assert rcm <= SOLVER and err <= SOLVER
        np.testing.assert_allclose([rcm, err], [a.rcm_error, a.tip_error], atol=EXACT)
        assert max(_fk_errors(s, b.ik.q, p)) <= SOLVER  # IPOPT's point: the same zero residual
        assert np.all(a.ik.q >= lo) and np.all(a.ik.q <= hi)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    direction=st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1),
    radius=st.floats(0.0, 0.03),
)
def test_lm_route_reaches_every_target_near_home(direction, radius):
    """Every target within 3 cm of panda's home tip, solved from home: both goals by FK
    within 1e-9 m, inside the joint limits."""
    s = _trocar_setup("panda")
    if "panda" not in _LM:
        _LM["panda"] = _home_tip(s)
    ik, q, tip = _LM["panda"]
    p = tip + radius * np.asarray(direction) / np.linalg.norm(direction)
    r = ik.solve(p, q)
    assert r.ik.success and max(_fk_errors(s, r.ik.q, p)) <= SOLVER
    m = s.chain.model
    assert np.all(r.ik.q >= m.lowerPositionLimit) and np.all(r.ik.q <= m.upperPositionLimit)


_LM: dict[str, tuple] = {}


def test_lm_route_keeps_a_binding_joint_limit():
    """panda's first joint boxed to ±0.01 rad around home: the projected LM reaches the
    target with that joint inside its box (the six others make up for it)."""
    s = _trocar_setup("panda")
    _, q, tip = _home_tip(s)
    model = pin.Model(s.chain.model)
    model.lowerPositionLimit[0], model.upperPositionLimit[0] = q[0] - 0.01, q[0] + 0.01
    p = tip + np.array([0.0, 0.02, 0.0])  # sideways: the base joint would turn
    free = RcmIK(s.chain.model, s.chain.tool).solve(p, q)
    assert abs(free.ik.q[0] - q[0]) > 0.01  # the limit binds
    r = RcmIK(model, s.chain.tool).solve(p, q)
    assert r.ik.success and r.rcm_error <= SOLVER and r.tip_error <= SOLVER
    assert q[0] - 0.01 <= r.ik.q[0] <= q[0] + 0.01
    assert np.all(r.ik.q >= model.lowerPositionLimit) and np.all(r.ik.q <= model.upperPositionLimit)


def test_lm_route_raises_on_an_unreachable_target(setup):
    s = setup
    ik, q, tip = _home_tip(s)
    p = np.asarray(s.tool.trocar) + np.array([0.0, 0.0, -3.0])  # 3 m below the trocar
    with pytest.raises(UnreachablePoseError) as err:
        ik.solve(p, q)
    r = err.value.result
    assert r.solver == "lm" and not r.success and r.status == "stationary"
    assert str(err.value) == (
        f"unreachable target: IK of frame 'rcm_tip' (lm, stationary, {r.iterations} it): "
        f"residual {r.residual_norm:.3g} > reach_tol 1e-09, position error "
        f"{r.position_error:.3g} m, constraint violation {r.constraint_violation:.3g}; the "
        "solver stopped at a stationary point, which a local method cannot tell from a local "
        "minimum: valid targets lie in the image of the joint limits (retry with restarts > "
        "0 to rule out a local minimum)"
    )
    assert r.residual_norm >= 3.0 - 0.15 - 1.5  # farther than any arm reaches (1.5 m)
    rcm, tip_err = _fk_errors(s, r.q, p)
    np.testing.assert_allclose([rcm, tip_err], [r.constraint_violation, r.position_error],
                               atol=EXACT)  # fmt: skip
    assert not ik.solve(p, q, raise_on_failure=False).ik.success
    # IPOPT's route raises the same error type; its point keeps the RCM, the LM's does not
    with pytest.raises(UnreachablePoseError) as nlp:
        RcmIK(s.chain.model, s.chain.tool, solver="ipopt").solve(p, q)
    assert nlp.value.result.constraint_violation <= SOLVER < r.constraint_violation


def test_solver_choice_is_checked():
    s = make_setup("panda", (0.4, 0.0, 0.3))
    with pytest.raises(InvalidInputError) as err:
        RcmIK(s.chain.model, s.chain.tool, tolerance=1e-3, solver="lm")
    assert str(err.value) == (
        "solver 'lm' solves the RCM as an equality; valid: tolerance=0, or solver='ipopt' "
        "for an RCM tolerance"
    )
    with pytest.raises(InvalidInputError) as err:
        RcmIK(s.chain.model, s.chain.tool, solver="snopt")  # type: ignore[arg-type]
    assert str(err.value) == "solver must be 'auto', 'lm' or 'ipopt', got 'snopt'"
    assert RcmIK(s.chain.model, s.chain.tool, tolerance=1e-3).solver == "ipopt"


def test_ik_with_rcm_tolerance_stays_within_it(setup):
    s = setup
    tolerance = 2e-3
    ik = RcmIK(s.chain.model, s.chain.tool, tolerance=tolerance)
    p = surgical_path("circle", s.cone, rate=1.0).p[1]
    r = ik.solve(p, s.home[s.chain.active])
    rcm, tip = _fk_errors(s, r.ik.q, p)
    assert rcm <= tolerance * (1 + 1e-9) and tip <= 1e-8  # ocp.rcm.TOLERANCE_REACH


def test_tracking_ocp_keeps_the_rcm_along_the_path(setup):
    s = setup
    dt = 0.01
    path = surgical_path("circle", s.cone, rate=1 / dt, duration=0.2)
    q0 = start_configuration(s, path.p[0])
    guess = track(RcmQP(s.chain.model, s.chain.tool, dt), q0, path.p).q
    ocp = RcmTrackingOCP(s.chain.model, s.chain.tool, n_intervals=len(path.t) - 1, dt=dt)
    r = ocp.solve(path.p, q0, guess=guess)
    assert r.success
    assert r.rcm_error.max() <= SOLVER and r.tip_error.max() <= 1e-4
    for k in (1, len(r.q) - 1):
        rcm, tip = _fk_errors(s, r.q[k], path.p[k])
        np.testing.assert_allclose([rcm, tip], [r.rcm_error[k], r.tip_error[k]], atol=EXACT)
    v = np.diff(r.q, axis=0) / dt
    assert np.all(np.abs(v) <= s.chain.model.velocityLimit * (1 + 1e-6))
    # node torques of the twin against Pinocchio's RNEA on the same differences
    m, k = s.chain.model, 3
    vk, ak = (r.q[k + 1] - r.q[k - 1]) / (2 * dt), (r.q[k + 1] - 2 * r.q[k] + r.q[k - 1]) / dt**2
    np.testing.assert_allclose(r.tau[k - 1], pin.rnea(m, m.createData(), r.q[k], vk, ak),
                               rtol=0, atol=1e-9)  # fmt: skip
    limited = RcmTrackingOCP(m, s.chain.tool, n_intervals=len(path.t) - 1, dt=dt,
                             drive_limits=True).solve(path.p, q0, guess=guess)  # fmt: skip
    assert limited.success and limited.rcm_error.max() <= SOLVER
    assert np.all(np.abs(limited.tau) <= m.effortLimit * (1 + 1e-6))


def test_bad_input():
    s = make_setup("rcm_bevel")
    with pytest.raises(InvalidInputError) as err:
        tip_model(s.mech.model, s.tool.__class__(s.tool.axis_frame, 2, s.tool.tip_frame, 0.1,
                                                 s.tool.trocar))  # fmt: skip
    assert str(err.value) == (
        "a tip offset needs the tip frame to be the shaft frame; valid: tip_offset=0 or "
        "tip_frame = the shaft frame"
    )


def test_torque_peak_matches_the_casadi_twin(setup):
    from ocp.symbolic import SymbolicModel
    from rcm_pin.studies.rcm_comparison import run
    from rcm_pin.studies.rcm_metrics import metrics, torque_peak

    tr = run(setup, "arc", duration=0.03)
    mech, q, h = setup.mech, tr.q, 1e-3
    rnea = SymbolicModel(mech.model).rnea()
    v, a = (q[2:] - q[:-2]) / (2 * h), (q[2:] - 2 * q[1:-1] + q[:-2]) / h**2
    twin = max(
        float(np.abs(np.asarray(rnea(mech.to_pin(x), mech.v_pin(y), mech.v_pin(z)))).max())
        for x, y, z in zip(q[1:-1], v, a)
    )
    np.testing.assert_allclose(torque_peak(tr), twin, rtol=1e-10)  # twin = Pinocchio to 1e-10
    m = metrics(tr, cone=False)
    np.testing.assert_allclose(m.velocity_peak, np.abs(np.diff(q, axis=0)).max() / h, rtol=1e-12)
    assert m.rcm_max <= 1e-6 and m.tip_max <= 1e-4 and np.isnan(m.cone_manipulability_min)
