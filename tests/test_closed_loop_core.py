"""Closed-loop core: sidecar, loader, Pinocchio closures, typed errors."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from rcm_pin.closed_loop import check_rendered, from_urdf_and_sidecar, load_closed
from rcm_pin.closed_loop.loader import render_closed
from rcm_pin.closed_loop.position import direct_position, inverse_position
from rcm_pin.closed_loop.sidecar import spec_from_urdf, spec_from_yaml
from rcm_pin.errors import (
    InvalidInputError,
    UnknownMechanismError,
    UnreachablePoseError,
    XacroArgumentError,
)
from rcm_pin.render import URDF_DIR


def test_committed_urdf_and_sidecar_are_fresh():
    assert check_rendered() == []


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar"])
def test_sidecar_yaml_equals_xacro_element(name):
    urdf, text = render_closed(name)
    assert spec_from_yaml(text) == spec_from_urdf(urdf)
    m = from_urdf_and_sidecar(URDF_DIR / f"{name}.urdf")
    n = load_closed(name)
    assert m.driven == n.driven and m.passive == n.passive
    assert [c.frame_a for c in m.closures] == [c.frame_a for c in n.closures]


def test_partition_and_constraint_models(m3, m5):
    assert m3.driven == ("A1", "A2", "A3") and m3.passive == ("B1", "C1", "B2", "B3")
    assert m3.n_constraints == 4 and m3.dof == 3
    assert m5.driven == ("A1", "A2") and m5.extra_drives == ("B1", "B2")
    for cm in m3.constraint_models:
        assert cm.type == pin.ContactType.CONTACT_3D


def test_planar_point_closure_is_rank_deficient_in_3d(m3):
    q = inverse_position(m3, np.array([0.02, -0.01, 0.2])).solutions[0].q
    pin.computeJointJacobians(m3.model, m3.data, q)
    for cm, cd in zip(m3.constraint_models, m3.constraint_datas, strict=True):
        cm.calc(m3.model, m3.data, cd)
    full = pin.getConstraintsJacobian(m3.model, m3.data, m3.constraint_models, m3.constraint_datas)
    assert full.shape == (6, 7)
    assert np.linalg.matrix_rank(full, 1e-10) == 4  # the z rows vanish
    assert np.allclose(full[[2, 5]], 0.0)


def test_fast_jacobian_equals_pinocchio_constraint_jacobian_and_fd(m3):
    q = inverse_position(m3, np.array([0.01, 0.03, -0.1])).solutions[2].q
    e1, j1 = m3.residual_and_jacobian(q)
    e2, j2 = m3.residual_and_jacobian_pin(q)
    assert np.max(np.abs(j1 - j2)) < 1e-14 and np.max(np.abs(e1)) < 1e-12
    eps = 1e-7
    fd = np.array(
        [
            (m3.closure_residual(q + eps * d) - m3.closure_residual(q - eps * d)) / (2 * eps)
            for d in np.eye(7)
        ]
    ).T
    assert np.max(np.abs(fd - j1)) < 1e-8


def test_error_unknown_mechanism():
    with pytest.raises(UnknownMechanismError) as exc:
        load_closed("delta")
    assert str(exc.value) == "unknown closed mechanism 'delta'; valid: planar_3rrr, five_bar"


def test_error_negative_length():
    with pytest.raises(XacroArgumentError) as exc:
        load_closed("planar_3rrr", distal_1=-0.1)
    assert str(exc.value) == "xacro argument distal_1=-0.1 must be a positive length [m]"


def test_error_unknown_xacro_argument():
    with pytest.raises(XacroArgumentError, match="unknown xacro argument 'radius'"):
        load_closed("five_bar", radius=0.1)


def test_error_pose_shape(m3):
    with pytest.raises(InvalidInputError) as exc:
        inverse_position(m3, np.zeros(2))
    assert str(exc.value) == "pose must have shape (3,), got (2,)"


def test_error_nan_drives(m3):
    with pytest.raises(InvalidInputError) as exc:
        direct_position(m3, np.array([np.nan, 0.0, 0.0]))
    assert str(exc.value) == "q_drives has NaN or infinite entries: [nan, 0.0, 0.0]"


def test_error_unreachable_pose(m3):
    with pytest.raises(UnreachablePoseError) as exc:
        inverse_position(m3, np.array([1.0, 0.0, 0.0]))
    assert str(exc.value) == (
        "planar_3rrr: pose [1.0, 0.0, 0.0] is outside the workspace (a leg cannot reach its "
        "platform point: |l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 fails)"
    )


def test_error_drives_without_assembly(m5):
    with pytest.raises(UnreachablePoseError) as exc:
        direct_position(m5, np.array([np.pi, 0.0]))
    assert str(exc.value) == (
        "five_bar: drives [3.141592653589793, 0.0] admit no assembly (loop cannot close)"
    )
