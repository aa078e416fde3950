"""Trajectory-tracking OCP (ocp.tracking) on paper 000's reference and on a generic arm."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

import rcm_pin
from ocp import SymbolicModel, TrackingOCP
from ocp import paper000 as paper
from ocp.models import model_from_urdf
from rcm_pin.errors import InvalidInputError

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def feasible():
    """N = 50, drive-limit constraints present but not binding."""
    ocp, mech = paper.build(n_intervals=50)
    return ocp, mech, paper.solve(ocp, mech, effort_limits=mech.model.effortLimit.copy())


def test_exact_solution_tracks_the_reference():
    """Analytic IK + inverse dynamics is an exact tracking solution: its kinematics hit
    p_ref(t), and integrating the forward dynamics under its efforts stays on p_ref."""
    ocp, mech = paper.build(n_intervals=5, drive_limits=False)
    sm = SymbolicModel(mech.model)
    fk, fd = sm.frame_placement("tool"), sm.forward_dynamics()
    t = np.linspace(0.0, paper.HORIZON, 101)
    ex = paper.exact_solution(mech, t)
    p = np.array([np.asarray(fk(q)[0]).ravel() for q in ex.q])
    assert np.abs(p - paper.reference_position(t)).max() < 1e-12
    n = mech.nq

    def rhs(tk: float, x: np.ndarray) -> np.ndarray:
        tau = paper.exact_solution(mech, np.array([tk])).tau[0]
        return np.concatenate([x[n:], np.asarray(fd(x[:n], x[n:], tau)).ravel()])

    sol = solve_ivp(
        rhs,
        (0.0, paper.HORIZON),
        paper.initial_state(mech),
        t_eval=t,
        rtol=1e-11,
        atol=1e-12,
        method="DOP853",
    )
    p_sim = np.array([np.asarray(fk(q)[0]).ravel() for q in sol.y[:n].T])
    assert np.abs(p_sim - paper.reference_position(t)).max() < 1e-6


def test_ocp_recovers_the_exact_solution(feasible):
    """The default route: Newton's method on the reduced problem, kept since the limits do
    not bind; the zero-cost solution to rounding (q within 1e-14; v and tau, derived with
    1/h and 1/h^2 from q and through two RNEA implementations, within 1e-9)."""
    ocp, mech, res = feasible
    assert res.success and (res.solver, res.status) == ("newton", "Step_Converged")
    assert np.all(np.abs(res.tau) <= mech.model.effortLimit)  # the limits do not bind
    assert res.tracking_error < 1e-12
    exact = paper.discrete_exact(ocp, mech)  # analytic IK + RNEA on the collocation grid
    assert np.abs(res.q_colloc - exact.q).max() < 1e-14
    assert np.abs(res.v_colloc - exact.v).max() < 1e-9
    assert np.abs(res.tau - exact.tau).max() < 1e-9
    # against the continuous exact solution only the discretisation error remains
    cont = paper.exact_solution(mech, res.t_colloc)
    assert np.abs(res.q_colloc - cont.q).max() < 1e-9
    assert np.abs(res.tau - cont.tau).max() < 2e-3


def test_discretisation_error_is_second_order_in_the_efforts():
    errs = []
    for n in (25, 50):
        ocp, mech = paper.build(n_intervals=n, drive_limits=False)
        res = paper.solve(ocp, mech)
        errs.append(np.abs(res.tau - paper.exact_solution(mech, res.t_colloc).tau).max())
    assert 3.0 < errs[0] / errs[1] < 5.5


def test_limited_drives_give_a_feasible_degraded_solution():
    ocp, mech = paper.build(n_intervals=40, lock_wrist=True)
    lim = np.full(mech.nq, np.inf)
    lim[:3] = 0.8 * paper.peak_efforts(mech, 401)[:3]
    res = paper.solve(ocp, mech, effort_limits=lim)
    assert res.success
    assert np.all(np.abs(res.tau) <= lim + 1e-7)
    assert 5e-3 < res.tracking_error < 5e-2  # cannot track with 80 % of the peak efforts
    data = mech.model.createData()  # the efforts are the model's inverse dynamics
    for q, v, a, tau in zip(res.q_colloc, res.v_colloc, res.a_colloc, res.tau):
        assert np.abs(pin.rnea(mech.model, data, q, v, a) - tau).max() < 1e-9


def test_fatrop_matches_ipopt():
    ocp, mech = paper.build(n_intervals=20, solver="fatrop", drive_limits=False)
    res = paper.solve(ocp, mech)
    exact = paper.discrete_exact(ocp, mech)
    assert res.solver == "fatrop" and res.tracking_error < 1e-9
    assert np.abs(res.tau - exact.tau).max() < 1e-6


def test_generic_arm_tracks_a_circle():
    """ur5 from the catalogue: the Mechanism's tool frame is the tracked frame."""
    mech = rcm_pin.load("ur5")
    q0 = np.array([0.3, -1.2, 1.4, -0.4, 1.2, 0.1])
    centre = rcm_pin.tool_pose(mech, q0)[:3, 3].copy()

    def circle(t: np.ndarray) -> np.ndarray:
        s = 2.0 * np.pi * t
        return centre + 0.05 * np.stack([np.sin(s), 1.0 - np.cos(s), 0.0 * s], axis=-1)

    ocp = TrackingOCP(
        mech,
        horizon=1.0,
        n_intervals=20,
        drive_limits=False,
        posture_weights=np.full(6, 1e-2),
    )
    res = ocp.solve(circle, np.concatenate([q0, np.zeros(6)]), posture=q0)
    assert res.success and res.tracking_error < 1e-4
    data = mech.model.createData()  # the tracked frame is ur5's tool0, by Pinocchio
    for q, p in zip(res.q_colloc, res.p):
        pin.framesForwardKinematics(mech.model, data, q)
        assert np.abs(data.oMf[mech.model.getFrameId("tool0")].translation - p).max() < 1e-12


def test_invalid_inputs():
    ocp, mech = paper.build(n_intervals=5, drive_limits=False)
    x0 = paper.initial_state(mech)
    with pytest.raises(InvalidInputError):
        ocp.solve(np.zeros((3, 3)), x0)
    with pytest.raises(InvalidInputError, match="drive_limits"):
        ocp.solve(paper.reference_position, x0, effort_limits=np.ones(6))
    with pytest.raises(InvalidInputError, match="nq == nv"):
        TrackingOCP(model_from_urdf(DATA / "mimic_tree.urdf"), "marker", horizon=1.0)
    with pytest.raises(InvalidInputError, match="frame is required"):
        TrackingOCP(mech.model, horizon=1.0)


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar", "four_bar"])
def test_closed_mechanisms_are_refused(name):
    """The tracking OCP stays serial: a closed mechanism raises a typed error that lists
    the valid (serial) catalogue entries."""
    mech = rcm_pin.load(name)
    with pytest.raises(InvalidInputError, match=r"serial mechanism.*rcm_bevel.*ur5"):
        TrackingOCP(mech, horizon=1.0, n_intervals=5)
    with pytest.raises(InvalidInputError, match="loop closures"):
        paper.build(name, n_intervals=5)


def test_paper_example_needs_the_rcm_tool_centre():
    with pytest.raises(InvalidInputError, match=r"q3·e4.*rcm_bevel"):
        paper.build("ur5", n_intervals=5)
