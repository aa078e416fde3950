"""Closed-loop core: sidecar, loading, Pinocchio closures, rank-revealing Newton, errors."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from rcm_pin.catalog.files import check_rendered, render_default
from rcm_pin.errors import (
    InvalidInputError,
    UnknownMechanismError,
    UnreachablePoseError,
    XacroArgumentError,
)
from rcm_pin.model.constraints import constraint_models, pin_constraint_jacobian
from rcm_pin.model.resources import urdf_dir
from rcm_pin.model.sidecar import description_from_yaml, read_description, to_yaml

CLOSED = ("planar_3rrr", "five_bar", "four_bar")


def test_committed_urdf_and_sidecar_are_fresh():
    assert check_rendered() == []


@pytest.mark.parametrize("name", CLOSED)
def test_sidecar_yaml_equals_xacro_element(name):
    urdf = render_default(name)
    desc = read_description(urdf)
    assert description_from_yaml(to_yaml(desc)).loops == desc.loops
    by_path = rcm_pin.load(urdf_dir() / f"{name}.urdf")  # URDF + the YAML beside it
    by_name = rcm_pin.load(name)
    assert by_path.loops.drives == by_name.loops.drives
    assert by_path.loops.passive == by_name.loops.passive
    assert [c.rows for c in by_path.loops.closures] == [c.rows for c in by_name.loops.closures]
    assert by_path.family is by_name.family


def test_yaml_sidecar_without_the_urdf_element(tmp_path, m3):
    """A LAAS-style file pair: the tree without <rcm_pin>, the loops in the YAML only."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(m3.urdf)
    root.remove(root.find("rcm_pin"))
    (tmp_path / "tree.urdf").write_text(ET.tostring(root, encoding="unicode"))
    (tmp_path / "tree.yaml").write_text((urdf_dir() / "planar_3rrr.yaml").read_text())
    m = rcm_pin.load(tmp_path / "tree.urdf")
    assert m.loops.drives == ("A1", "A2", "A3") and m.family.name == "planar_3rrr"
    q = m3.home
    np.testing.assert_allclose(m.closure_residual(q), m3.closure_residual(q), atol=1e-15)


def test_partition_and_closures(m3, m5):
    assert m3.loops.drives == ("A1", "A2", "A3") and m3.loops.passive == ("B1", "C1", "B2", "B3")
    assert m3.loops.n_rows == 4 and m3.loops.dof == 3
    assert m5.loops.drives == ("A1", "A2") and m5.loops.extra_drives == ("B1", "B2")
    assert all(c.kind == "3d" and c.rows == (0, 1) for c in m3.loops.closures)
    assert all(c.world_rows == (0, 1) for c in m3.loops.closures)  # planar: no z row
    for cm in constraint_models(m3.model, m3.loops):
        assert cm.type == pin.ContactType.CONTACT_3D


def test_planar_point_closure_is_rank_deficient_in_3d(m3):
    q = rcm_pin.inverse(m3, np.array([0.02, -0.01, 0.2])).solutions[0].q
    model = m3.model
    data = model.createData()
    cms = pin.StdVec_RigidConstraintModel()
    cds = pin.StdVec_RigidConstraintData()
    for cm in constraint_models(model, m3.loops):
        cms.append(cm)
        cds.append(cm.createData())
    pin.computeJointJacobians(model, data, q)
    for cm, cd in zip(cms, cds, strict=True):
        cm.calc(model, data, cd)
    full = pin.getConstraintsJacobian(model, data, cms, cds)
    assert full.shape == (6, 7)
    assert np.linalg.matrix_rank(full, 1e-10) == 4  # the z rows vanish
    assert np.allclose(full[[2, 5]], 0.0)


@pytest.mark.parametrize("name", CLOSED)
def test_frame_jacobian_route_equals_pinocchio_constraint_jacobian_and_fd(name):
    mech = rcm_pin.load(name)
    q = mech.home
    e1, j1 = mech.residual_and_jacobian(q)
    j2 = pin_constraint_jacobian(mech.model, mech.loops, q)
    assert np.max(np.abs(j1 - j2)) < 1e-14 and np.max(np.abs(e1)) < 1e-12
    eps = 1e-7
    fd = np.array(
        [
            (mech.closure_residual(q + eps * d) - mech.closure_residual(q - eps * d)) / (2 * eps)
            for d in np.eye(mech.nq)
        ]
    ).T
    assert np.max(np.abs(fd - j1)) < 1e-8


def test_six_d_closure_jacobian_matches_finite_differences(m3):
    """A 6d closure (frames coincide) of the 3-RRR's platform vertex: Jlog6 route vs FD."""
    from dataclasses import replace

    from rcm_pin.model.loops import build_loops, residual_and_jacobian

    spec = m3.loops.spec
    six = replace(spec, closures=(replace(spec.closures[0], kind="6d", rows=()),))
    loops = build_loops(m3.model, six)
    rng = np.random.default_rng(3)
    data = m3.model.createData()
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, m3.nq)
        _, jac = residual_and_jacobian(m3.model, data, loops, q)
        eps = 1e-7
        fd = np.array([(residual_and_jacobian(m3.model, data, loops, q + eps * d)[0]
                        - residual_and_jacobian(m3.model, data, loops, q - eps * d)[0]) / (2 * eps)
                       for d in np.eye(m3.nq)]).T  # fmt: skip
        assert np.max(np.abs(fd - jac)) < 1e-6


def test_redundant_rows_are_resolved_by_rank(m3):
    """Keep every row of the planar point closures (z too): Newton still converges and the
    mobility by rank is 3 while the row count says 1."""
    from dataclasses import replace

    from rcm_pin.model.loops import build_loops
    from rcm_pin.model.newton import constraint_rank, solve_passive

    spec = m3.loops.spec
    full = replace(spec, closures=tuple(replace(c, rows=()) for c in spec.closures))
    loops = build_loops(m3.model, full)
    assert loops.n_rows == 6
    home = m3.home
    guess = home.copy()
    guess[loops.passive_q] += 0.05
    q, it, res = solve_passive(m3.model, m3.model.createData(), loops, home[loops.drive_q], guess)
    # converged (RESIDUAL_TOL) at Newton's quadratic rate from 0.05 rad, a handful of
    # iterations; redundant rows that slowed it to a linear rate would take dozens
    assert res < 1e-13 and it < 10
    np.testing.assert_allclose(q, home, atol=1e-10)
    from rcm_pin.model.loops import residual_and_jacobian

    jac = residual_and_jacobian(m3.model, m3.model.createData(), loops, q)[1]
    assert m3.nv - constraint_rank(jac) == 3 and m3.nv - loops.n_rows == 1


def test_error_unknown_mechanism():
    with pytest.raises(UnknownMechanismError) as exc:
        rcm_pin.load("delta")
    assert str(exc.value).startswith("unknown mechanism 'delta'; valid: rcm_bevel, ")


def test_error_negative_length():
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load("planar_3rrr", distal_1=-0.1)
    assert str(exc.value) == (
        "distal_1=-0.1 is out of range for planar_3rrr.urdf.xacro; valid: (0, 10] [m] "
        "(l2_1: |B_1 C_1| (omitted in the paper's F_1))"
    )


def test_error_unknown_xacro_argument():
    with pytest.raises(XacroArgumentError, match="unknown xacro argument 'radius'"):
        rcm_pin.load("five_bar", radius=0.1)


def test_error_pose_shape(m3):
    with pytest.raises(InvalidInputError) as exc:
        rcm_pin.inverse(m3, np.zeros(2))
    assert str(exc.value) == (
        "target has shape (2,); valid: (3,) values of x, y, rz of frame platform_centre"
    )


def test_error_nan_drives(m3):
    with pytest.raises(InvalidInputError) as exc:
        rcm_pin.forward(m3, np.array([np.nan, 0.0, 0.0]))
    assert str(exc.value) == "drives has NaN or infinite entries: [nan, 0.0, 0.0]"


def test_error_unreachable_pose(m3):
    with pytest.raises(UnreachablePoseError) as exc:
        rcm_pin.inverse(m3, np.array([1.0, 0.0, 0.0]))
    assert str(exc.value) == (
        "planar_3rrr: pose [1.0, 0.0, 0.0] is outside the workspace (a leg cannot reach its "
        "platform point: |l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 fails)"
    )


def test_error_drives_without_assembly(m5):
    with pytest.raises(UnreachablePoseError) as exc:
        rcm_pin.forward(m5, np.array([np.pi, 0.0]))
    assert str(exc.value) == (
        "five_bar: drives [3.141592653589793, 0.0] admit no assembly (the loops cannot close); "
        "valid: drive values inside the workspace of five_bar"
    )
