"""Every joint a URDF can hold (docs/joints.md): one coordinate per independent joint,
continuous joints one unbounded angle (cos/sin inside the Mechanism), continuous mimic
pairs, floating / planar joints refused by name.

References are plain Pinocchio on the URDF file, with the (cos θ, sin θ) pairs and the
mimic joints' angles built here from the angles."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, SOLVER
from hypothesis import given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin.analysis.jacobians import tool_jacobian
from rcm_pin.cli import main
from rcm_pin.control import SimulationOptions, simulate
from rcm_pin.dynamics import (
    coriolis_matrix,
    forward_dynamics,
    gravity,
    inverse_dynamics,
    mass_matrix,
    nonlinear_effects,
    total_energy,
)
from rcm_pin.errors import InvalidInputError, UnsupportedJointError
from rcm_pin.mechanisms.arms import robots_dir

ERD = robots_dir()
KINOVA = ERD / "kinova_description/robots/kinova.urdf"
PENDULUM = ERD / "double_pendulum_description/urdf/double_pendulum_continuous.urdf"
DATA = Path(__file__).parent / "data"
SMALL = DATA / "continuous_joints.urdf"
PARALLELOGRAM = DATA / "double_parallelogram_continuous.urdf"
#: mimic joints of the fixtures: follower -> (primary, multiplier, offset), as written there
MIMICS = {
    SMALL: {"cont_follower": ("cont_primary", -2.0, 0.3), "rev_follower": ("rev", 0.5, -0.1)},
    PARALLELOGRAM: {
        "pitch_bottom_joint": ("pitch", -1.0, 0.0),
        "pitch_end_joint": ("pitch", 1.0, 0.0),
        "pitch_top_joint": ("pitch", -1.0, 0.0),
        "shaft_pitch_joint": ("pitch", 1.0, 0.0),
    },
}
CASES = [
    (KINOVA, "j2s6s200_end_effector"),
    (PENDULUM, "link2"),
    (SMALL, "tool_link"),
    (PARALLELOGRAM, "tool_link"),
]
_LOADED: dict[Path, rcm_pin.Mechanism] = {}


def mech_of(path: Path, tool: str) -> rcm_pin.Mechanism:
    if path not in _LOADED:
        _LOADED[path] = rcm_pin.load(str(path), tool_frame=tool)
    return _LOADED[path]


def plain(path: Path, angles: dict[str, float]) -> tuple[pin.Model, np.ndarray]:
    """Pinocchio's no-mimic model of the file and its q: every joint from its angle or
    its mimic relation, a continuous joint as (cos, sin)."""
    model = pin.buildModelFromUrdf(str(path))
    q = pin.neutral(model)
    for name, (primary, k, off) in MIMICS.get(path, {}).items():
        angles = {**angles, name: k * angles[primary] + off}
    for j in range(1, model.njoints):
        jm, a = model.joints[j], angles[model.names[j]]
        if jm.nq == 2:
            q[jm.idx_q : jm.idx_q + 2] = math.cos(a), math.sin(a)
        else:
            q[jm.idx_q] = a
    return model, q


def sample(mech: rcm_pin.Mechanism, rng: np.random.Generator) -> np.ndarray:
    lo = np.where(np.isfinite(mech.lower), mech.lower, -3 * np.pi)
    hi = np.where(np.isfinite(mech.upper), mech.upper, 3 * np.pi)
    return rng.uniform(lo, hi)


@pytest.mark.parametrize(("path", "tool"), CASES, ids=lambda c: getattr(c, "stem", c))
def test_one_coordinate_per_independent_joint(path, tool):
    mech = mech_of(path, tool)
    model = pin.buildModelFromUrdf(str(path))
    independent = [
        model.names[j]
        for j in range(1, model.njoints)
        if model.names[j] not in MIMICS.get(path, {})
    ]
    assert mech.joint_names == tuple(independent) and mech.nq == mech.nv == len(independent)
    for k, name in enumerate(mech.joint_names):
        if model.joints[model.getJointId(name)].nq == 2:  # continuous: one unbounded angle
            assert (mech.lower[k], mech.upper[k]) == (-np.inf, np.inf) and mech.revolute[k]


@pytest.mark.parametrize(("path", "tool"), CASES, ids=lambda c: getattr(c, "stem", c))
def test_pose_equals_plain_pinocchio(path, tool):
    mech = mech_of(path, tool)
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = sample(mech, rng)
        model, qp = plain(path, dict(zip(mech.joint_names, q, strict=True)))
        data = model.createData()
        pin.framesForwardKinematics(model, data, qp)
        expected = data.oMf[model.getFrameId(tool)].homogeneous
        pose = rcm_pin.tool_pose(mech, q)
        assert np.abs(pose - expected).max() < EXACT
        assert abs(np.linalg.det(pose[:3, :3]) - 1.0) < EXACT


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-50.0, 50.0), min_size=6, max_size=6))
def test_kinova_pose_at_any_angles_is_plain_pinocchio(angles):
    """Any real angles (continuous joints unbounded, revolute ones outside their limits
    too): the pose is Pinocchio's at (cos θ, sin θ), 2π-periodic in each continuous angle."""
    mech, tool = mech_of(KINOVA, "j2s6s200_end_effector"), "j2s6s200_end_effector"
    q = np.array(angles)
    model, qp = plain(KINOVA, dict(zip(mech.joint_names, q, strict=True)))
    data = model.createData()
    pin.framesForwardKinematics(model, data, qp)
    pose = rcm_pin.tool_pose(mech, q)
    assert np.abs(pose - data.oMf[model.getFrameId(tool)].homogeneous).max() < EXACT
    turned = q.copy()
    turned[mech.continuous] += 2 * np.pi
    assert np.abs(rcm_pin.tool_pose(mech, turned) - pose).max() < 1e-11


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-50.0, 50.0), min_size=2, max_size=2))
def test_continuous_angles_round_trip(angles):
    """Any angle: to_pin writes (cos, sin), from_pin reads it back modulo 2π."""
    mech = mech_of(PENDULUM, "link2")
    q = np.array(angles)
    qp = mech.to_pin(q)
    assert np.abs(qp - np.array([np.cos(q), np.sin(q)]).T.ravel()).max() < EXACT
    back = mech.from_pin(qp)
    assert np.abs(np.angle(np.exp(1j * (back - q)))).max() < 1e-11
    assert np.all(np.abs(back) <= np.pi)


@pytest.mark.parametrize(("path", "tool"), CASES, ids=lambda c: getattr(c, "stem", c))
def test_jacobian_matches_finite_differences(path, tool):
    mech = mech_of(path, tool)
    q, h = sample(mech, np.random.default_rng(3)), 1e-6
    J = tool_jacobian(mech, q)
    for k in range(mech.nq):
        dq = np.zeros(mech.nq)
        dq[k] = h
        Tp, Tm = rcm_pin.tool_pose(mech, q + dq), rcm_pin.tool_pose(mech, q - dq)
        lin = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        ang = pin.log3(Tp[:3, :3] @ Tm[:3, :3].T) / (2 * h)
        assert np.abs(J[:, k] - np.concatenate([lin, ang])).max() < 1e-7


@pytest.mark.parametrize(("path", "tool"), CASES, ids=lambda c: getattr(c, "stem", c))
def test_no_mimic_model_through_the_coupling_is_the_file(path, tool):
    """Every frame of mech.model_full at q_full = G q + offset (continuous joints of mimic
    pairs there unbounded revolute) and of the mimic model is where the file puts it."""
    mech = mech_of(path, tool)
    rng = np.random.default_rng(13)
    for _ in range(10):
        q = sample(mech, rng)
        model, qp = plain(path, dict(zip(mech.joint_names, q, strict=True)))
        data = model.createData()
        pin.framesForwardKinematics(model, data, qp)
        for m, x in (
            (mech.model_full, mech.coupling.q_full(mech.to_pin(q))),
            (mech.model, mech.to_pin(q)),
        ):
            d = m.createData()
            pin.framesForwardKinematics(m, d, x)
            for f in model.frames:
                got = d.oMf[m.getFrameId(f.name, f.type)].homogeneous
                assert (
                    np.abs(got - data.oMf[model.getFrameId(f.name, f.type)].homogeneous).max()
                    < EXACT
                )


def test_kinova_inverse_round_trip():
    mech = mech_of(KINOVA, "j2s6s200_end_effector")
    q = np.array([0.4, 2.5, 2.0, -1.0, 2.2, 0.7])
    target = rcm_pin.tool_pose(mech, q)
    result = rcm_pin.inverse(mech, target)
    assert result.count >= 1
    for sol in result.solutions:
        assert np.abs(rcm_pin.tool_pose(mech, sol.q) - target).max() < SOLVER


def _projection(path: Path, mech: rcm_pin.Mechanism, model: pin.Model) -> np.ndarray:
    """G_v (nv_full, n) of the mimic relations, written from MIMICS."""
    Gv = np.zeros((model.nv, mech.nv))
    for j in range(1, model.njoints):
        name = model.names[j]
        primary, k, _ = MIMICS.get(path, {}).get(name, (name, 1.0, 0.0))
        Gv[model.joints[j].idx_v, mech.joint_names.index(primary)] = k
    return Gv


@pytest.mark.parametrize(("path", "tool"), CASES, ids=lambda c: getattr(c, "stem", c))
def test_dynamics_equal_plain_pinocchio(path, tool):
    """M = G_vᵀ M_full G_v and τ = G_vᵀ RNEA_full (virtual work; G_v = I without mimic)."""
    mech = mech_of(path, tool)
    rng = np.random.default_rng(11)
    q, v, a = sample(mech, rng), rng.normal(size=mech.nv), rng.normal(size=mech.nv)
    model, qp = plain(path, dict(zip(mech.joint_names, q, strict=True)))
    data, Gv = model.createData(), _projection(path, mech, model)
    M_full = pin.crba(model, data, qp)
    M_full = np.triu(M_full) + np.triu(M_full, 1).T
    tau = Gv.T @ pin.rnea(model, data, qp, Gv @ v, Gv @ a)
    M = Gv.T @ M_full @ Gv
    assert np.array_equal(mech.coupling.Gv, Gv)  # the coupling of continuous joints too
    C, g = coriolis_matrix(mech, q, v), gravity(mech, q)
    assert np.abs(C @ v + g - nonlinear_effects(mech, q, v)).max() < 1e-10
    assert np.abs(mass_matrix(mech, q) - M).max() < EXACT * max(1.0, np.abs(M).max())
    assert np.abs(inverse_dynamics(mech, q, v, a) - tau).max() < 1e-10
    assert np.abs(forward_dynamics(mech, q, v, inverse_dynamics(mech, q, v, a)) - a).max() < 1e-9


def test_simulation_hot_path_is_the_dynamics():
    """simulate's hot path (cos/sin written for the continuous joints) on kinova."""
    from rcm_pin.control.hot_path import SerialPlant

    mech = mech_of(KINOVA, "j2s6s200_end_effector")
    rng = np.random.default_rng(17)
    q, v, tau = sample(mech, rng), rng.normal(size=mech.nv), rng.normal(size=mech.nv)
    expected = forward_dynamics(mech, q, v, tau)
    assert np.abs(SerialPlant(mech).accel(q, v, tau) - expected).max() < 1e-9


def test_passive_double_pendulum_keeps_its_energy():
    """simulate integrates the angles (unbounded) of a continuous double pendulum."""
    mech = mech_of(PENDULUM, "link2")
    q0, v0 = np.array([1.0, -0.5]), np.array([0.0, 3.0])
    r = simulate(mech, None, 1.0, q0, v0, SimulationOptions(samples=21, rtol=1e-10, atol=1e-10))
    energy = [total_energy(mech, q, v) for q, v in zip(r.q, r.v, strict=True)]
    assert r.completed and max(energy) - min(energy) < 1e-7 * abs(energy[0])


def test_parallelogram_keeps_its_remote_centre():
    """The shaft line (z of shaft_link) passes through A = rcm_point for every configuration."""
    mech = mech_of(PARALLELOGRAM, "tool_link")
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = sample(mech, rng)
        shaft, a = (
            rcm_pin.frame_pose(mech, q, "shaft_link"),
            rcm_pin.frame_pose(mech, q, "rcm_point"),
        )
        offset = a[:3, 3] - shaft[:3, 3]
        assert np.linalg.norm(np.cross(shaft[:3, 2], offset)) < EXACT


def test_continuous_mimic_parsed_as_unbounded_revolute():
    """The rewritten model has the kinematics of the file's (FK above); its followers take
    no coordinate and its models carry infinite limits, never the placeholder."""
    mech = mech_of(SMALL, "tool_link")
    assert mech.joint_names == ("rev", "cont", "cont_primary", "slide")
    assert mech.continuous.tolist() == [1]  # cont: (cos, sin) in Pinocchio's q
    for model in (mech.model, mech.model_full):
        jm = model.joints[model.getJointId("cont_primary")]
        assert (jm.nq, jm.nv) == (1, 1)
        assert model.lowerPositionLimit[jm.idx_q] == -np.inf
        assert (model.effortLimit[jm.idx_v], model.velocityLimit[jm.idx_v]) == (5.0, 2.0)


def _robot(joint: str) -> str:
    return (
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="hinge" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        f'<joint name="base" type="{joint}"><parent link="b"/><child link="c"/></joint></robot>'
    )


@pytest.mark.parametrize(("kind", "sizes"), [("floating", "nq=7, nv=6"), ("planar", "nq=4, nv=3")])
def test_floating_and_planar_joints_refused_by_name(kind, sizes):
    with pytest.raises(UnsupportedJointError) as err:
        rcm_pin.from_urdf(_robot(kind), name="r", tool_frame="c")
    assert str(err.value) == (
        f"r: joint 'base' is {kind} ({sizes}); valid: revolute, continuous, prismatic, fixed "
        "or mimic joints (write a floating or planar base as a chain of prismatic and "
        "revolute joints)"
    )
    assert isinstance(err.value, InvalidInputError)


def test_robot_without_name_refused_with_reason():
    """example-robot-data's ur3.urdf is a xacro macro file rendered without a robot."""
    with pytest.raises(InvalidInputError, match=r"<robot name=\.\.\.> with at least one <link>"):
        rcm_pin.load(str(ERD / "ur_description/urdf/ur3.urdf"), tool_frame="tool0")


def test_cli_fk_and_ik_on_kinova_by_path(capsys):
    q = [0.4, 2.5, 2.0, -1.0, 2.2, 0.7]
    argv = ["fk", str(KINOVA), "--tool-frame", "j2s6s200_end_effector"]
    code = main([*argv, "--q", ",".join(map(str, q)), "--json"])
    payload = json.loads(capsys.readouterr().out)
    pose = np.array(payload["solutions"][0]["pose"])
    mech = mech_of(KINOVA, "j2s6s200_end_effector")
    assert code == 0 and np.abs(pose - rcm_pin.tool_pose(mech, np.array(q))).max() < EXACT
    assert abs(np.linalg.det(pose[:3, :3]) - 1.0) < EXACT
    assert payload["joint_names"] == list(mech.joint_names)
    target = ";".join(",".join(repr(float(x)) for x in row) for row in pose[:3])
    code = main(
        ["ik", str(KINOVA), "--tool-frame", "j2s6s200_end_effector", "--pose", target, "--json"]
    )
    payload = json.loads(capsys.readouterr().out)
    assert code == 0 and payload["count"] >= 1
    for sol in payload["solutions"]:
        assert np.abs(rcm_pin.tool_pose(mech, np.array(sol["q"])) - pose).max() < SOLVER


def _mimic_robot(primary: str, follower: str) -> str:
    """Two branches from the base: joint ``p`` and ``follower`` mimicking ``primary``
    (Pinocchio walks sibling branches in the order of their joint names)."""
    limit = '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
    return (
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        f'<joint name="p" type="revolute"><parent link="a"/><child link="b"/>{limit}</joint>'
        f'<joint name="{follower}" type="revolute"><parent link="a"/><child link="c"/>{limit}'
        f'<mimic joint="{primary}"/></joint></robot>'
    )


def test_mimic_failures_name_the_joints():
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.from_urdf(_mimic_robot("nope", "f"), name="r", tool_frame="c")
    assert str(err.value) == (
        "r: joint 'f' mimics 'nope', which the URDF does not have; valid: a <mimic joint=...> "
        "naming one of its joints"
    )
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.from_urdf(_mimic_robot("p", "f"), name="r", tool_frame="c")
    assert str(err.value) == (
        "r: joint 'f' mimics 'p', which Pinocchio meets after it in its depth-first walk of the "
        "tree; valid: a primary on the follower's path from the root or on an earlier branch"
    )
    mech = rcm_pin.from_urdf(_mimic_robot("p", "z"), name="r", tool_frame="c")
    assert mech.joint_names == ("p",)


def test_casadi_twin_writes_cos_sin():
    """The compiled right-hand side's map (ocp.kernels.serial_rhs) is the Mechanism's."""
    import casadi as ca

    from ocp.kernels.serial_rhs import _to_pin

    mech = mech_of(KINOVA, "j2s6s200_end_effector")
    q, v = ca.SX.sym("q", mech.nq), ca.SX.sym("v", mech.nv)
    qp, vp = _to_pin(mech, q, v)
    f = ca.Function("to_pin", [q, v], [qp, vp])
    x, xd = np.random.default_rng(2).normal(size=(2, mech.nq)) * 4.0
    got_q, got_v = (np.asarray(a).ravel() for a in f(x, xd))
    assert np.abs(got_q - mech.to_pin(x)).max() < EXACT
    assert np.abs(got_v - mech.v_pin(xd)).max() < EXACT


def test_workspace_samples_one_turn_of_a_continuous_joint():
    from rcm_pin.analysis.workspace import sample_joints

    mech = mech_of(KINOVA, "j2s6s200_end_effector")
    qs = sample_joints(mech, 500, seed=1)
    cont = mech.continuous
    assert cont.tolist() == [0, 3, 5]
    assert np.all(np.abs(qs[:, cont]) <= np.pi) and np.ptp(qs[:, cont], axis=0).min() > 5.0


def test_cli_refuses_a_planar_joint_with_exit_2(capsys, tmp_path):
    path = tmp_path / "planar_base.urdf"
    path.write_text(_robot("planar"))
    code = main(["fk", str(path), "--tool-frame", "c", "--q", "0.1", "--json"])
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and error["type"] == "UnsupportedJointError"
    assert error["message"].startswith("planar_base: joint 'base' is planar (nq=4, nv=3)")


def test_casadi_model_of_a_continuous_mimic_file_is_the_mechanism():
    """ocp.models.model_from_urdf parses as rcm_pin.load: the CasADi twin's pose of the
    double parallelogram's tool is the Mechanism's."""
    from ocp.models import model_from_urdf
    from ocp.symbolic import SymbolicModel

    mech = mech_of(PARALLELOGRAM, "tool_link")
    sm = SymbolicModel(model_from_urdf(PARALLELOGRAM))
    place = sm.frame_placement(mech.tool_frame_id)
    q = sample(mech, np.random.default_rng(19))
    p, R = (np.asarray(x) for x in place(mech.to_pin(q)))
    pose = rcm_pin.tool_pose(mech, q)
    assert np.abs(p.ravel() - pose[:3, 3]).max() < EXACT and np.abs(R - pose[:3, :3]).max() < EXACT


def test_papers_order_with_a_continuous_joint():
    """<rcm_pin coordinates=...> in another order: the continuous joint keeps its angle."""
    element = '<rcm_pin tool_frame="tool_link" coordinates="slide cont rev {}"/></robot>'
    text = SMALL.read_text().replace("</robot>", element.format("cont_primary"))
    mech = rcm_pin.from_urdf(text, name="reordered")
    base = mech_of(SMALL, "tool_link")
    assert mech.joint_names == ("slide", "cont", "rev", "cont_primary")
    assert mech.continuous.tolist() == [1] and mech.lower[1] == -np.inf
    q = sample(base, np.random.default_rng(23))
    reordered = q[[3, 1, 0, 2]]
    assert np.abs(rcm_pin.tool_pose(mech, reordered) - rcm_pin.tool_pose(base, q)).max() < EXACT
    with pytest.raises(InvalidInputError, match="cont_follower have no coordinate"):
        rcm_pin.from_urdf(SMALL.read_text().replace("</robot>", element.format("cont_follower")))


def test_duplicate_names_are_named():
    text = SMALL.read_text().replace('name="slide"', 'name="cont"')
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.from_urdf(text, name="twice", tool_frame="tool_link")
    assert str(err.value) == "twice: joint name 'cont' is used twice; valid: unique joint names"


def test_a_robot_without_moving_joints_is_refused():
    urdf = (
        '<robot name="statue"><link name="base"/><link name="head"/>'
        '<joint name="neck" type="fixed"><parent link="base"/><child link="head"/></joint>'
        "</robot>"
    )
    with pytest.raises(UnsupportedJointError) as info:
        rcm_pin.from_urdf(urdf, "statue", tool_frame="head")
    assert str(info.value) == (
        "statue: no moving joint (every joint is fixed or a mimic follower); valid: a URDF "
        "with at least one revolute, continuous or prismatic joint"
    )


def test_a_continuous_joint_of_a_closed_mechanism_is_one_angle(tmp_path):
    """The LAAS five-bar with its first joint made continuous: one coordinate per joint,
    names unique, and the same closure and frames as the revolute original at any q."""
    laas = Path(__file__).parent / "data" / "laas"
    text = (laas / "five_bar.urdf").read_text().replace('type="revolute"', 'type="continuous"', 1)
    (tmp_path / "five_bar.urdf").write_text(text)
    (tmp_path / "five_bar.yaml").write_text((laas / "five_bar.yaml").read_text())
    mech = rcm_pin.load(tmp_path / "five_bar.urdf")
    ref = rcm_pin.load(laas / "five_bar.urdf")
    assert mech.joint_names == ref.joint_names
    assert len(set(mech.joint_names)) == len(mech.joint_names) == mech.nq == mech.nv
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, mech.nq)
        np.testing.assert_allclose(
            mech.closure_residual(mech.q_pin(q)), ref.closure_residual(ref.q_pin(q)), atol=EXACT
        )
