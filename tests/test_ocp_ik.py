"""IK NLPs (ocp.ik) against the analytic IK of the RCM mechanisms and on the catalogue's
reference arms (panda, ur5 through ``rcm_pin.load``), checked by Pinocchio."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp import AxisThroughPoint, IKProblem, OrientationCone
from ocp.models import model_from_urdf
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.mechanisms.rcm import analytic_ik, closed_form

DATA = Path(__file__).parent / "data"

N_POSES = 1000
BRANCH_TOL = 1e-8


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def _diff(q: np.ndarray, ref: np.ndarray, prismatic: int = 2) -> np.ndarray:
    """Coordinate differences, angles wrapped (q3 is a length)."""
    d = _wrap(q - ref)
    d[..., prismatic] = (q - ref)[..., prismatic]
    return np.abs(d)


def _wide_limits(nq: int) -> tuple[np.ndarray, np.ndarray]:
    """All analytic branches admissible: angles in [-pi, pi], |q3| <= 0.25 m."""
    hi = np.full(nq, np.pi)
    hi[2] = 0.25
    return -hi, hi


@pytest.mark.parametrize("name, n_poses", [("rcm_bevel", N_POSES), ("rcm_bevel_4dof", 300)])
def test_converges_to_the_nearby_analytic_branch(name, n_poses):
    """Random reachable poses; start within 0.3 rad (0.03 m for q3) of a random analytic
    branch; the LM solution must be that branch to 1e-8 (success rate reported), and every
    solution must be one of the analytic branches."""
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(11)
    q_true = rng.uniform(mech.lower, mech.upper, size=(n_poses, mech.nq))
    wrist = closed_form.wrist_type(mech)
    poses = (
        closed_form.tool_pose(q_true, wrist or "zyz")
        if mech.nq == 6
        else np.array([rcm_pin.tool_pose(mech, q) for q in q_true])
    )
    branches = analytic_ik.ik_pose(poses, wrist).q  # (n, n_branches, nq)
    lo, hi = _wide_limits(mech.nq)
    prob = IKProblem(mech.model, "tool", lower=mech.to_pin(lo), upper=mech.to_pin(hi))
    scale = np.full(mech.nq, 0.3)
    scale[2] = 0.03
    hits, other, skipped = 0, 0, 0
    for k in range(n_poses):
        b = rng.integers(branches.shape[1])
        target = branches[k, b]
        if not np.isfinite(target).all():
            skipped += 1
            continue
        q0 = target + rng.uniform(-scale, scale)
        res = prob.solve(poses[k], mech.to_pin(q0), raise_on_failure=False)
        q = mech.from_pin(res.q)
        if res.success and _diff(q, target).max() < BRANCH_TOL:
            hits += 1
        elif res.success:  # a valid solution on another branch (near a wrist singularity)
            assert _diff(q[None], branches[k]).max(1).min() < 1e-7
            other += 1
    rate = hits / (n_poses - skipped)
    print(
        f"\n{name}: {hits}/{n_poses - skipped} converged to the start's branch "
        f"({rate:.1%}), {other} to another branch"
    )
    assert rate >= 0.98


def test_cold_start_with_restarts_solves_every_pose():
    mech = rcm_pin.load("rcm_bevel")
    rng = np.random.default_rng(2)
    prob = IKProblem(mech.model, "tool", restarts=10)
    for q in rng.uniform(mech.lower, mech.upper, size=(100, 6)):
        res = prob.solve(closed_form.tool_pose(q))
        assert res.success and res.position_error < 1e-10 and res.orientation_error < 1e-10


def test_position_mode_recovers_analytic_position_branch():
    mech = rcm_pin.load("rcm_bevel")
    rng = np.random.default_rng(3)
    prob = IKProblem(mech.model, "tool", mode="position")
    q = rng.uniform(mech.lower, mech.upper, size=(200, 6))
    p = closed_form.tool_position(q)
    ref = analytic_ik.ik_position(p, q3_sign=1).q[:, 0]  # principal branch, within limits
    for k in range(len(q)):
        res = prob.solve(p[k])
        assert np.abs(mech.from_pin(res.q)[:3] - ref[k]).max() < 1e-8
        assert np.isnan(res.orientation_error)


def test_unreachable_targets_raise_typed_errors():
    mech = rcm_pin.load("rcm_bevel")
    prob = IKProblem(mech.model, "tool", mode="position")
    with pytest.raises(UnreachablePoseError) as info:  # beyond the q3 limit of 0.12 m
        prob.solve(np.array([0.0, 0.05, 0.2]))
    result = info.value.result  # type: ignore[attr-defined]
    assert result.position_error == pytest.approx(0.2062 - 0.12, abs=1e-3)
    mech4 = rcm_pin.load("rcm_bevel_4dof")
    pose = np.eye(4)
    pose[:3, 3] = [0.03, 0.0, 0.08]  # p off the tool z axis: no 4-DOF configuration
    with pytest.raises(UnreachablePoseError):
        IKProblem(mech4.model, "tool", restarts=3).solve(pose)
    ur5 = rcm_pin.load("ur5")
    far = IKProblem(ur5, mode="position", constraints=[AxisThroughPoint((0.3, 0.0, 0.5))])
    with pytest.raises(UnreachablePoseError):
        far.solve(np.array([3.0, 0.0, 0.5]))


def _ur5_pose(seed: int) -> tuple[pin.Model, np.ndarray, np.ndarray]:
    model = rcm_pin.load("ur5").model
    q = np.random.default_rng(seed).uniform(-2.0, 2.0, 6)
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return model, q, data.oMf[model.getFrameId("tool0")].homogeneous.copy()


def test_solvers_agree_on_ur5():
    model, q, pose = _ur5_pose(1)
    prob = IKProblem(model, "tool0")
    sols = {s: prob.solve(pose, q + 0.2, solver=s) for s in ("lm", "ipopt", "sqpmethod")}
    for name, res in sols.items():
        assert res.solver == name and res.success
        assert np.abs(res.q - q).max() < 1e-7


def test_the_compiled_lm_is_the_least_squares_reference_on_ur5():
    """ocp.ik_lm is a compiled speed twin of rcm_pin.analysis.serial_ik (SciPy's bounded
    least squares on Pinocchio's output error): from seeded random starts near seeded
    random poses both reach the same configuration (1e-9, solver results)."""
    from rcm_pin.analysis.serial_ik import TOL, solve_one

    mech = rcm_pin.load("ur5")
    prob = IKProblem(mech)
    rng = np.random.default_rng(24)
    for q_true in rng.uniform(-2.0, 2.0, (30, mech.nq)):
        pin.framesForwardKinematics(mech.model, mech.data, mech.to_pin(q_true))
        frame = mech.data.oMf[mech.output.frame_id]
        q0 = q_true + rng.uniform(-0.05, 0.05, mech.nq)
        twin = prob.solve(frame.homogeneous, mech.to_pin(q0), solver="lm")
        ref, err = solve_one(mech, mech.output.value(frame), mech.output, q0)
        assert twin.success and err < TOL
        np.testing.assert_allclose(mech.from_pin(twin.q), ref, rtol=0, atol=1e-9)
        np.testing.assert_allclose(ref, q_true, rtol=0, atol=1e-9)


def test_rcm_and_cone_constraints_on_ur5():
    model, q, pose = _ur5_pose(1)
    p, z = pose[:3, 3], pose[:3, 2]
    point = p + 0.1 * z + np.array([0.0, 0.02, 0.0])  # not on the current tool axis
    data, fid = model.createData(), model.getFrameId("tool0")
    for tol in (0.0, 1e-3):
        prob = IKProblem(
            model,
            "tool0",
            mode="position",
            constraints=[AxisThroughPoint(tuple(point), tolerance=tol)],
        )
        res = prob.solve(p, q)
        assert res.solver == "ipopt" and res.position_error < 1e-8
        pin.framesForwardKinematics(model, data, res.q)
        d, axis = point - data.oMf[fid].translation, data.oMf[fid].rotation[:, 2]
        assert np.linalg.norm(d - (d @ axis) * axis) <= tol + 1e-8
    cone = IKProblem(
        model, "tool0", mode="position", constraints=[OrientationCone((0.0, 0.0, -1.0), 0.2)]
    )
    res = cone.solve(p, q)
    pin.framesForwardKinematics(model, data, res.q)
    assert res.position_error < 1e-8
    assert data.oMf[fid].rotation[:, 2] @ np.array([0.0, 0.0, -1.0]) >= np.cos(0.2) - 1e-8


def test_continuous_and_mimic_joints():
    model = model_from_urdf(DATA / "mimic_tree.urdf")
    data, fid = model.createData(), model.getFrameId("tool_link")
    prob = IKProblem(model, "tool_link")
    rng = np.random.default_rng(4)
    pin.seed(4)  # pin.randomConfiguration draws from Pinocchio's own generator
    for _ in range(20):
        q = pin.randomConfiguration(model)
        pin.framesForwardKinematics(model, data, q)
        q0 = pin.integrate(model, q, rng.uniform(-0.1, 0.1, model.nv))
        for solver in ("lm", "ipopt"):
            res = prob.solve(data.oMf[fid].homogeneous, q0, solver=solver)
            assert res.position_error < 1e-8 and res.orientation_error < 1e-8
            assert abs(res.q[6] ** 2 + res.q[7] ** 2 - 1.0) < 1e-9  # the (cos, sin) pair


def test_jit_gives_the_same_solution():
    mech = rcm_pin.load("rcm_bevel_4dof")
    q = np.array([0.2, -0.3, 0.08, 0.5])
    pose = rcm_pin.tool_pose(mech, q)
    plain = IKProblem(mech.model, "tool").solve(pose, mech.to_pin(q + 0.1))
    jit = IKProblem(mech.model, "tool", jit=True).solve(pose, mech.to_pin(q + 0.1))
    assert np.abs(plain.q - jit.q).max() < 1e-12 and plain.iterations == jit.iterations


def test_bad_inputs():
    mech = rcm_pin.load("rcm_bevel")
    prob = IKProblem(mech.model, "tool")
    with pytest.raises(InvalidInputError):
        prob.solve(np.zeros(3))  # a position in pose mode
    with pytest.raises(InvalidInputError):
        prob.solve(np.diag([1.0, 1.0, -1.0, 1.0]))  # not a rotation
    with pytest.raises(InvalidInputError):
        prob.solve(np.eye(4), q0=np.zeros(3))
    with pytest.raises(InvalidInputError):
        IKProblem(mech.model, "tool", constraints=[OrientationCone((0, 0, 1.0), 0.1)]).solve(
            np.eye(4), solver="lm"
        )
    with pytest.raises(InvalidInputError):
        AxisThroughPoint((0.0, 0.0, 0.0), axis=(0.0, 0.0, 0.0))


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_catalogue_arms_reach_random_tool_poses(name):
    """The example-robot-data arms from the catalogue (serial, no RCM frame): IK of the
    entry's tool frame (the default of IKProblem(mech)), checked by Pinocchio forward
    kinematics (position to 1e-9 m, rotation to 1e-8: the weighted residual's reach_tol
    1e-9 with orientation weight 0.1) and against the joint limits."""
    mech = rcm_pin.load(name)
    assert mech.loops is None and mech.rcm is None
    prob = IKProblem(mech, restarts=10)
    assert prob.fid == mech.tool_frame_id
    data, fid = mech.model.createData(), mech.tool_frame_id
    rng = np.random.default_rng(9)
    lo, hi = np.maximum(mech.lower, -np.pi), np.minimum(mech.upper, np.pi)
    for k, q in enumerate(rng.uniform(lo, hi, size=(30, mech.nq))):
        pose = rcm_pin.tool_pose(mech, q)
        solver = "lm" if k % 10 else "ipopt"  # the NLP from a warm start
        q0 = None if solver == "lm" else mech.to_pin(q + 0.05)
        res = prob.solve(pose, q0, solver=solver)
        pin.framesForwardKinematics(mech.model, data, res.q)
        assert np.abs(data.oMf[fid].translation - pose[:3, 3]).max() < 1e-9, (name, k, solver)
        assert np.abs(data.oMf[fid].rotation - pose[:3, :3]).max() < 1e-8, (name, k, solver)
        q_sol = mech.from_pin(res.q)
        assert np.all(q_sol >= mech.lower - 1e-12) and np.all(q_sol <= mech.upper + 1e-12)
    position = IKProblem(mech, mode="position").solve(pose[:3, 3])
    pin.framesForwardKinematics(mech.model, data, position.q)
    assert np.abs(data.oMf[fid].translation - pose[:3, 3]).max() < 1e-9


def test_output_mode_of_a_serial_mechanism_is_its_pose():
    """mode="output" on a serial Mechanism solves its tool pose (x, y, z, rotation), from a
    4x4 pose or the output's value vector (p, then R row by row), like mode="pose"."""
    mech = rcm_pin.load("rcm_bevel")
    q = np.array([0.3, -0.2, 0.09, 0.4, 0.5, 0.6])
    pose = rcm_pin.tool_pose(mech, q)
    q0 = mech.to_pin(q + 0.1)
    ref = IKProblem(mech).solve(pose, q0)
    out = IKProblem(mech, mode="output")
    for target in (pose, np.concatenate([pose[:3, 3], pose[:3, :3].reshape(9)])):
        res = out.solve(target, q0)
        assert res.success and np.abs(res.q - ref.q).max() < 1e-12
    with pytest.raises(InvalidInputError, match="mode='output'"):
        IKProblem(mech, "output_link", mode="output")
