"""Frame Jacobians of a Mechanism from Pinocchio, in Mechanism coordinates.

``J = getFrameJacobian(tool, LOCAL_WORLD_ALIGNED)`` (rows [v; ω] of the tool centre),
and its time derivative J̇ with a = J·q̈ + J̇·q̇ (classical acceleration).

**Pinocchio 4.1 on mimic models**: ``getFrameJacobian`` (every reference frame) and
``getFrameClassicalAcceleration`` agree with the no-mimic model projected through the
coupling (J = J_full·Gv) to 1e-16, but ``getFrameJacobianTimeVariation`` after
``computeJointJacobiansTimeVariation`` is wrong in ``LOCAL`` and ``LOCAL_WORLD_ALIGNED``
(errors of order 1 in the linear rows of the columns after the mimic joints); the
``WORLD`` variant is right. :func:`jacobian_derivative` therefore takes J̇ in ``WORLD``
and shifts it to the tool centre p itself:

    J_lwa = X·J_w,  X = [[I, −[p]×], [0, I]],   J̇_lwa = X·J̇_w + [[0, −[ṗ]×], [0, 0]]·J_w.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def tool_jacobian(mech: Mechanism, q: ArrayLike) -> FloatArray:
    """Tool Jacobian (6, n), rows [v; ω] of the tool centre, LOCAL_WORLD_ALIGNED.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].

    Returns:
        J with [v; ω] = J·q̇, columns in Mechanism order.
    """
    q = mech.check_q(q)
    pin.computeJointJacobians(mech.model, mech.data, mech.to_pin(q))
    pin.updateFramePlacements(mech.model, mech.data)
    J = pin.getFrameJacobian(mech.model, mech.data, mech.tool_frame_id, LWA)
    return np.asarray(J[:, mech.v_index], dtype=float)


def jacobian_derivative(mech: Mechanism, q: ArrayLike, qd: ArrayLike) -> FloatArray:
    """Time derivative J̇ (6, n) of :func:`tool_jacobian` along q̇ (WORLD route, see module).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        qd: coordinate rates (n,) [rad/s, m/s].

    Returns:
        J̇ such that a = J·q̈ + J̇·q̇ (classical acceleration of the tool centre).
    """
    q = mech.check_q(q)
    qd = mech.check_v(qd, "qd")
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    vpin = np.zeros(model.nv)
    idx = mech.v_index
    vpin[idx] = qd
    pin.computeJointJacobiansTimeVariation(model, data, mech.to_pin(q), vpin)
    pin.updateFramePlacements(model, data)
    Jw = pin.getFrameJacobian(model, data, fid, pin.ReferenceFrame.WORLD)
    dJw = pin.getFrameJacobianTimeVariation(model, data, fid, pin.ReferenceFrame.WORLD)
    p = data.oMf[fid].translation
    out = dJw.copy()
    out[:3] -= np.cross(p, dJw[3:].T).T  # X·J̇_w: v_p = v_o + ω × p = v_o − p × ω
    pd = (Jw[:3] - np.cross(p, Jw[3:].T).T) @ vpin  # tool-centre velocity ṗ
    out[:3] -= np.cross(pd, Jw[3:].T).T
    return np.asarray(out[:, idx], dtype=float)


__all__ = ["LWA", "jacobian_derivative", "tool_jacobian"]
