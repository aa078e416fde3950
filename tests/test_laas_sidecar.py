"""LAAS sidecars as *example-parallel-robots* writes them (tests/data/laas, fixtures of our
own: only ``closed_loop``, ``type``, ``name_mot``; joints without a position range; every
link with an inertia). Each result is checked by a second route."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from laas_fixtures import DATA, FIXTURES, OUTPUT, no_output_message

import rcm_pin
from rcm_pin.analysis.assembly_modes import MODE_TOL, placement_key
from rcm_pin.analysis.closed_singularity import drive_singularities
from rcm_pin.analysis.loop_velocity import passive_velocity
from rcm_pin.dynamics.constrained import forward_dynamics, pin_constraint_dynamics
from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.model.constraints import pin_constraint_jacobian
from rcm_pin.model.limits import unbounded_joints
from rcm_pin.model.newton import constraint_rank
from rcm_pin.model.sidecar import description_from_yaml

EXACT = 1e-12  # identities at round-off
SOLVED = 1e-9  # solver results


@pytest.fixture(scope="module", params=sorted(FIXTURES))
def laas(request):
    name = request.param
    return name, rcm_pin.load(DATA / f"{name}.urdf")


def test_load_reads_only_the_laas_keys(laas):
    name, mech = laas
    spec = FIXTURES[name]
    assert mech.loops is not None and not mech.output.present
    assert mech.loops.drives == spec["drives"] and mech.loops.dof == len(spec["drives"])
    assert [c.kind for c in mech.loops.closures] == list(spec["kinds"])
    assert np.all(mech.lower == -np.inf) and np.all(mech.upper == np.inf)
    assert np.all(mech.model.lowerPositionLimit == -np.inf)
    assert mech.nq == spec["nq"]


def test_home_is_assembled_and_mobility_has_the_rank_count(laas):
    _, mech = laas
    q = mech.home
    assert np.max(np.abs(mech.closure_residual(mech.q_pin(q)))) < EXACT
    mob = rcm_pin.mobility(mech)
    assert mob.rank_mobility == mech.loops.dof
    assert mob.rank_mobility == mech.nv - constraint_rank(mech.constraint_jacobian(q))


def test_forward_returns_distinct_assembled_modes(laas):
    name, mech = laas
    drives = mech.home[mech.loops.drive_q]
    res = rcm_pin.forward(mech, drives, all_modes=True)
    assert len(res.solutions) >= FIXTURES[name]["min_modes"]
    keys = []
    for s in res.solutions:
        assert np.max(np.abs(mech.closure_residual(mech.q_pin(s.q)))) < EXACT  # route 2
        np.testing.assert_allclose(s.q[mech.loops.drive_q], drives, atol=EXACT)
        keys.append(placement_key(mech, s.q))
    for i in range(len(keys)):
        for j in range(i):
            assert np.max(np.abs(keys[i] - keys[j])) >= MODE_TOL


def test_closure_jacobian_against_finite_differences_and_pinocchio(laas):
    _, mech = laas
    q = mech.q_pin(mech.home)
    _, jac = mech.residual_and_jacobian(q)
    h = 1e-6
    fd = np.column_stack(
        [
            (mech.closure_residual(q + h * e) - mech.closure_residual(q - h * e)) / (2 * h)
            for e in np.eye(mech.model.nv)
        ]
    )
    np.testing.assert_allclose(jac, fd, atol=1e-8)
    # Pinocchio's constraint Jacobian spans the same rows (equal where e = 0, 3d rows up
    # to the rotation R_a of the closure frame): same null space
    pj = pin_constraint_jacobian(mech.model, mech.loops, q)
    assert constraint_rank(np.vstack([jac, pj])) == constraint_rank(jac) == constraint_rank(pj)


def test_constrained_dynamics_two_routes(laas):
    _, mech = laas
    q = mech.q_pin(mech.home)
    rng = np.random.default_rng(7)
    qd_drives = rng.uniform(-1.0, 1.0, mech.loops.dof)
    v = passive_velocity(mech, q, qd_drives)
    assert np.max(np.abs(mech.constraint_jacobian(q) @ v)) < EXACT
    tau = rng.uniform(-0.5, 0.5, mech.model.nv)
    a_kkt, _ = forward_dynamics(mech, q, v, tau)
    a_pin = pin_constraint_dynamics(mech, q, v, tau)
    np.testing.assert_allclose(a_kkt, a_pin, atol=1e-7)
    m_mat = rcm_pin.dynamics.mass_matrix(mech, mech.home)
    m_full = pin.crba(mech.model_full, mech.data_full, mech.coupling.q_full(q))
    m_full = np.triu(m_full) + np.triu(m_full, 1).T
    gv = mech.coupling.Gv
    np.testing.assert_allclose(m_mat, gv.T @ m_full @ gv, atol=EXACT)


def test_vibrations_without_output(laas):
    _, mech = laas
    vib = rcm_pin.dynamics.natural_frequencies(mech, mech.home, 10.0)
    assert vib.output_modes.shape == (0, mech.loops.dof)
    c = np.full(mech.loops.dof, 10.0)
    w2 = vib.frequencies**2
    for j in range(mech.loops.dof):  # C φ = ω² M_q φ
        np.testing.assert_allclose(c * vib.modes[:, j], w2[j] * vib.mass @ vib.modes[:, j],
                                   atol=1e-9 * max(1.0, w2[j]))  # fmt: skip


def test_singularities_without_output_are_type2_only(laas):
    _, mech = laas
    rep = drive_singularities(mech, mech.home[mech.loops.drive_q])
    assert rep["output_coords"] == [] and rep["modes"]
    for m in rep["modes"]:
        assert m["type1"] is None and m["residual"] < EXACT
        jc = mech.constraint_jacobian(mech.q_pin(m["q"]))
        full_rank = constraint_rank(jc[:, mech.loops.passive_v]) == constraint_rank(jc)
        assert m["type2"] == (not full_rank) and m["measure_type2"] > 0.0


def test_commands_that_need_an_output_say_so(laas):
    name, mech = laas
    with pytest.raises(UnknownFrameError) as err:
        rcm_pin.inverse(mech, [0.0, 0.0])
    assert str(err.value) == no_output_message(mech, "the inverse position problem")
    from rcm_pin.control.scenario import scenarios

    with pytest.raises(UnknownFrameError) as err:
        scenarios(mech)
    assert str(err.value) == no_output_message(mech, "a simulation (its task)")


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_output_frame_keyword_and_inverse_round_trip(name):
    frame, coords = OUTPUT[name]
    mech = rcm_pin.load(DATA / f"{name}.urdf", output_frame=frame)
    assert mech.output.frame == frame and mech.output.coords == coords
    q = mech.home
    target = mech.output_value(mech.q_pin(q))
    res = rcm_pin.inverse(mech, target)
    for s in res.solutions:  # second route: forward kinematics of each working mode
        np.testing.assert_allclose(mech.output_value(mech.q_pin(s.q)), target, atol=SOLVED)
        assert np.max(np.abs(mech.closure_residual(mech.q_pin(s.q)))) < EXACT
    assert rcm_pin.load(DATA / f"{name}.urdf", tool_frame=frame).output == mech.output


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_ocp_ik_agrees_with_ik_and_honours_the_frame(name):
    from ocp.commands import ik_command

    frame, _ = OUTPUT[name]
    mech = rcm_pin.load(DATA / f"{name}.urdf", output_frame=frame)
    target = mech.output_value(mech.q_pin(mech.home))
    out = ik_command(rcm_pin.load(DATA / f"{name}.urdf", tool_frame=frame), pose=target)
    assert out["closure_residual"] < SOLVED
    np.testing.assert_allclose(list(out["output"].values()), target, atol=SOLVED)
    modes = rcm_pin.inverse(mech, target).solutions
    d = [np.max(np.abs(np.angle(np.exp(1j * (np.array(out["q"]) - s.q))))) for s in modes]
    assert min(d) < 1e-6  # the NLP's solution is one of the working modes of ik


def test_output_coords_keyword():
    mech = rcm_pin.load(DATA / "five_bar.urdf", output_frame="effector", output_coords="x y z")
    assert mech.output.coords == ("x", "y", "z")
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.load(DATA / "five_bar.urdf", output_coords="x y")
    assert str(err.value) == (
        "output_coords ['x', 'y'] given but five_bar names no output frame; valid: also an "
        "output frame (--output-frame FRAME [--output-coords 'x y'] on the command line, or "
        "rcm_pin.load(path, output_frame=FRAME, output_coords=('x', 'y')))"
    )
    with pytest.raises(InvalidInputError, match=r"^output_coords \['q'\]; valid: one or more"):
        rcm_pin.load(DATA / "five_bar.urdf", output_frame="effector", output_coords="q")


def test_missing_limit_rule():
    def urdf(limit: str) -> str:
        return (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
            f'<parent link="a"/><child link="b"/><axis xyz="0 0 1"/>{limit}</joint></robot>'
        )

    assert unbounded_joints(urdf("")) == {"j"}
    assert unbounded_joints(urdf('<limit effort="1" velocity="20"/>')) == {"j"}
    assert unbounded_joints(urdf('<limit lower="-1" effort="1" velocity="2"/>')) == set()
    assert unbounded_joints(urdf('<limit lower="0" upper="0" effort="1" velocity="2"/>')) == set()


def test_sidecar_keys_as_laas_writes_them():
    text = "closed_loop: [['a', 'b'], ['c', 'd']]\ntype: ['3D', '6d']\nname_mot: ['m1']\n"
    desc = description_from_yaml(text)
    assert [c.kind for c in desc.loops.closures] == ["3d", "6d"]
    assert desc.loops.output_frame == "" and desc.tool_frame == ""
    desc = description_from_yaml(text + "joint_name: ['s1']\njoint_type: ['SPHERICAL']\n")
    assert desc.joint_types == (("s1", "SPHERICAL"),)
    with pytest.raises(InvalidInputError) as err:
        description_from_yaml(text + "joint_name: ['s1', 's2']\njoint_type: ['FIXED']\n")
    assert str(err.value) == (
        "loop sidecar has 2 joint_name and 1 joint_type entries; valid: one type per joint name"
    )


def test_laas_joint_replacements(tmp_path):
    urdf = (DATA / "leg_6d.urdf").read_text()
    (tmp_path / "leg.urdf").write_text(urdf)
    base = (DATA / "leg_6d.yaml").read_text()
    (tmp_path / "leg.yaml").write_text(
        base + "joint_name: ['free_tip']\njoint_type: ['UJOINT_YZ']\n"
    )
    mech = rcm_pin.load(tmp_path / "leg.urdf")
    assert "free_tip" not in mech.model.names and {"free_tip_Y", "free_tip_Z"} <= set(
        mech.model.names
    )
    assert mech.nq == 6 and np.all(mech.lower == -np.inf)
    assert rcm_pin.mobility(mech).rank_mobility == 2  # the 6d closure holds the new rotation
    assert np.max(np.abs(mech.closure_residual(mech.q_pin(mech.home)))) < EXACT
    (tmp_path / "leg.yaml").write_text(base + "joint_name: ['knee']\njoint_type: ['FIXED']\n")
    fixed = rcm_pin.load(tmp_path / "leg.urdf")
    assert "knee" not in fixed.model.names and fixed.nq == 4
    (tmp_path / "leg.yaml").write_text(base + "joint_name: ['knee']\njoint_type: ['SPHERICAL']\n")
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.load(tmp_path / "leg.urdf")
    assert str(err.value) == (
        "sidecar joint_type 'SPHERICAL' of joint 'knee' is not supported; valid: FIXED, "
        "UJOINT_XY, UJOINT_XZ, UJOINT_YX, UJOINT_YZ, UJOINT_ZX, UJOINT_ZY (SPHERICAL: write the "
        "ball joint into the URDF as the loop's 3d closure)"
    )
    (tmp_path / "leg.yaml").write_text(base + "joint_name: ['nope']\njoint_type: ['FIXED']\n")
    with pytest.raises(UnknownFrameError, match=r"^sidecar joint_name 'nope' is not a joint of"):
        rcm_pin.load(tmp_path / "leg.urdf")


@pytest.mark.parametrize("name", ["five_bar", "leg_6d"])
def test_planar_fixtures_chebyshev_equals_the_rank_count(name):
    mob = rcm_pin.mobility(rcm_pin.load(DATA / f"{name}.urdf"))
    assert mob.chebyshev == mob.rank_mobility == 2  # a 6d closure welds in the plane: 3
    assert f"from the rank: {mob.rank_mobility}" in mob.describe()


SERIAL = """<robot name="arm2">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1"/>
    <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
  <link name="fore"><inertial><mass value="1"/>
    <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit effort="1" velocity="20"/></joint>
  <joint name="j2" type="revolute"><origin xyz="0.3 0 0"/><parent link="upper"/>
    <child link="fore"/><axis xyz="0 0 1"/><limit effort="1" velocity="20"/></joint>
  <joint name="t" type="fixed"><origin xyz="0.25 0 0"/><parent link="fore"/>
    <child link="tip"/></joint>
</robot>"""


def test_serial_joints_without_range_sample_and_solve():
    from rcm_pin.analysis.singularity import grid
    from rcm_pin.analysis.workspace import sample_joints

    mech = rcm_pin.from_urdf(SERIAL, "arm2", tool_frame="tip")
    assert np.all(mech.lower == -np.inf) and np.all(mech.upper == np.inf)
    np.testing.assert_array_equal(mech.home, [0.0, 0.0])  # mid-range rule: 0 when unbounded
    qs = sample_joints(mech, 50)
    assert np.all(np.abs(qs) <= np.pi)
    xs, ys, values = grid(mech, mech.home, 0, 1, n=3)
    np.testing.assert_allclose(xs, [-np.pi, 0.0, np.pi], atol=EXACT)
    assert values.shape == (3, 3)
    q = np.array([0.3, 0.5])
    target = rcm_pin.forward(mech, q).solutions[0].output
    res = rcm_pin.inverse(mech, target[:3], coords=("x", "y", "z"))
    assert res.solutions and all(s.within_limits for s in res.solutions)
    for s in res.solutions:  # second route: forward kinematics of each branch
        np.testing.assert_allclose(rcm_pin.forward(mech, s.q).solutions[0].output[:3],
                                   target[:3], atol=SOLVED)  # fmt: skip


def test_a_self_motion_is_named_in_the_method(tmp_path):
    """Two coaxial revolute joints closed by a 6d closure (as LAAS files cut revolute
    joints): one freedom more than the drives; the fixtures have none."""
    urdf = (DATA / "five_bar.urdf").read_text()
    spin = (
        '<link name="spin"><inertial><mass value="0.01"/><inertia ixx="1e-6" ixy="0" ixz="0" '
        'iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link><joint name="spin_a" type="revolute">'
        '<origin xyz="0.3 0 0"/><parent link="distal_1"/><child link="spin"/>'
        '<axis xyz="0 0 1"/><limit effort="1" velocity="20"/></joint>'
        '<link name="spin_b_link"/><joint name="spin_b" type="revolute">'
        '<origin xyz="0.3 0 0"/><parent link="distal_2"/><child link="spin_b_link"/>'
        '<axis xyz="0 0 1"/><limit effort="1" velocity="20"/></joint></robot>'
    )
    (tmp_path / "spun.urdf").write_text(urdf.replace("</robot>", spin))
    (tmp_path / "spun.yaml").write_text(
        "closed_loop: [['spin', 'spin_b_link']]\ntype: ['6d']\nname_mot: ['mot1', 'mot2']\n"
    )
    mech = rcm_pin.load(tmp_path / "spun.urdf")
    res = rcm_pin.forward(mech, mech.home[mech.loops.drive_q], all_modes=True)
    assert res.method.endswith(
        "; self-motion: nv − rank J_c exceeds the 2 drives by 1, modes along it that move "
        "frames are listed apart"
    )
    assert len(res.solutions) == 2  # the spin moves no frame origin: the two modes remain
    plain = rcm_pin.load(DATA / "five_bar.urdf")
    assert "self-motion" not in rcm_pin.forward(plain, plain.home[plain.loops.drive_q]).method
