"""Accuracy of any mechanism: the linear theory of paper 004 beside the nonlinear change.

Error variables θ: each joint placement of the model perturbed by a local twist
M_j' = M_j·exp(δ) (three translations [m], three small rotations [rad]; a rotation about
the joint axis is a joint offset). Outputs: the output coordinates' error
(:meth:`rcm_pin.model.output.Output.error`) and, where the mechanism has a remote centre,
the RCM offset c = (I − e eᵀ)(o − a) of its insertion axis.

* serial: the outputs at fixed coordinates q;
* closed: drives locked, the passive joints re-solved on the perturbed model (the
  closure Newton), so the error is the output's displacement the loops allow.

First order: central finite differences ∂f/∂θ (h = 1e-7); nonlinear: f(θ0 + δ) − f(θ0)
for the chosen error size δ; their relative difference is the linear theory's error. A
family may add design (xacro) parameters of its own (:mod:`rcm_pin.mechanisms.rcm.accuracy`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import solve_passive

COMPONENTS = ("dx", "dy", "dz", "rx", "ry", "rz")


def _outputs(
    mech: Mechanism, model: pin.Model, data: pin.Data, q_pin: np.ndarray, nominal: np.ndarray
) -> np.ndarray:
    """[output error vs nominal value; RCM offset c] at a Pinocchio configuration."""
    pin.framesForwardKinematics(model, data, q_pin)
    out = mech.output
    value = out.value(data.oMf[out.frame_id])
    parts = [out.error(value, nominal)]
    if mech.rcm is not None:
        a = data.oMf[mech.rcm.point_frame_id].translation
        axis = data.oMf[mech.rcm.axis_frame_id]
        e = axis.rotation[:, mech.rcm.axis]
        d = axis.translation - a
        parts.append(d - (d @ e) * e)
    return np.concatenate(parts)


def placement_change(
    mech: Mechanism, q: np.ndarray, joint: str, component: int
) -> Callable[[float], np.ndarray]:
    """δ -> change of the outputs for a placement error δ of one joint component."""
    if component not in range(6):
        raise InvalidInputError(f"component {component}; valid: 0..5 ({', '.join(COMPONENTS)})")
    jid = mech.model.getJointId(joint) if mech.model.existJointName(joint) else 0
    if jid == 0:
        raise InvalidInputError(
            f"joint {joint!r} not in {mech.name}; valid: {', '.join(mech.model.names[1:])}"
        )
    model = mech.model.copy()
    data = model.createData()
    M0 = mech.model.jointPlacements[jid].copy()
    q_pin = mech.q_pin(q)
    pin.framesForwardKinematics(mech.model, mech.data, q_pin)
    nominal = mech.output.value(mech.data.oMf[mech.output.frame_id])
    f0 = _outputs(mech, mech.model, mech.data, q_pin, nominal)

    def change(delta: float) -> np.ndarray:
        xi = np.zeros(6)
        xi[component] = delta
        model.jointPlacements[jid] = M0 * pin.exp6(xi)
        qp = q_pin
        if mech.loops is not None:
            qp, _, _ = solve_passive(
                model, data, mech.loops, q_pin[mech.loops.drive_q], q_pin, name=mech.name
            )
        return _outputs(mech, model, data, qp, nominal) - f0

    return change


def sensitivities(
    mech: Mechanism, q: Any, size: float = 1e-4, angle: float = np.radians(0.1), h: float = 1e-7
) -> dict[str, Any]:
    """Linear and nonlinear output changes for every joint placement component.

    Args:
        mech: the mechanism.
        q: configuration (n,) (closed: a closed configuration; its drives are locked).
        size: translation error [m] (default 0.1 mm).
        angle: rotation error [rad] (default 0.1°).
        h: finite-difference step.

    Returns:
        ``{"mechanism", "q", "rows"}``; each row: joint, component, error size, linear and
        nonlinear output change (norm of the output error part, and of the RCM offset),
        their relative difference.
    """
    q = mech.check_q(q)
    if mech.loops is not None and float(np.linalg.norm(mech.closure_residual(q))) > 1e-10:
        raise InvalidInputError(f"{mech.name}: q does not close the loops; valid: a closed q")
    dim = mech.output.dim
    rows = []
    joints = [mech.model.names[j] for j in range(1, mech.model.njoints)]
    for joint in joints:
        for k, comp in enumerate(COMPONENTS):
            change = placement_change(mech, q, joint, k)
            delta = size if k < 3 else angle
            lin = (change(h) - change(-h)) / (2 * h) * delta
            non = change(delta)
            rows.append(
                {
                    "joint": joint,
                    "component": comp,
                    "error": delta,
                    "linear_output": float(np.linalg.norm(lin[:dim])),
                    "nonlinear_output": float(np.linalg.norm(non[:dim])),
                    "linear_rcm": float(np.linalg.norm(lin[dim:])) if mech.rcm else None,
                    "nonlinear_rcm": float(np.linalg.norm(non[dim:])) if mech.rcm else None,
                    "relative_difference": float(
                        np.linalg.norm(non[:dim] - lin[:dim])
                        / max(float(np.linalg.norm(non[:dim])), 1e-300)
                    ),
                }
            )
    rows.sort(key=lambda r: -r["nonlinear_output"])
    return {"mechanism": mech.name, "q": q, "rows": rows}


def cramer(a_mat: np.ndarray, rhs: np.ndarray, min_det: float = 1e-12) -> np.ndarray:
    """x of A x = rhs by Cramer's rule, x_k = det A_k / det A (A_k: column k replaced by
    rhs), the form in which paper 004 writes the linear theory of accuracy.

    Raises:
        SingularConfigurationError: |det A| < ``min_det`` (a type-2 singularity: the linear
            theory has no denominator).
    """
    det = float(np.linalg.det(a_mat))
    if not abs(det) >= min_det:
        raise SingularConfigurationError(
            f"Cramer's rule: det A = {det:.3e} (type-2 singularity: no denominator); valid: a "
            f"configuration with |det A| >= {min_det:g}"
        )
    out = np.zeros(len(rhs))
    for k in range(len(rhs)):
        a_k = np.array(a_mat, dtype=float)
        a_k[:, k] = rhs
        out[k] = np.linalg.det(a_k) / det
    return out


__all__ = ["COMPONENTS", "cramer", "placement_change", "sensitivities"]
