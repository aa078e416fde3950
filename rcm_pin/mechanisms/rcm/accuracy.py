"""Accuracy: the linear theory of paper 004 applied to the RCM mechanisms.

Outputs, functions of a configuration q and an error vector θ:

- the tool pose (position p [m] and orientation, as a rotation vector [rad]);
- the RCM offset c [m]: the vector from A (the ``rcm`` frame) to the nearest point of the
  insertion line (the translation axis of pair 24, z of the ``working_organ`` frame
  through its origin o): c = (I − e eᵀ)(o − a). c = 0 for the nominal mechanism at every q;
  |c| is how far the tool line misses the trocar point.

Error variables θ:

1. xacro parameters (a *consistent* design change, re-rendered): l9, a7_x, a7_z, the tooth
   counts z13..z22 (bevel) or the pulley diameters d1..d4 (belt);
2. manufacturing errors of single parts: each joint placement of the rendered model
   perturbed by a local twist M_j' = M_j·exp(δ) (three translations [m], three small
   rotations [rad]; a rotation about the joint axis is a joint-offset / assembly-phase
   error, e.g. of a gear mesh or belt).

First order: central finite differences ∂f/∂θ (h = 1e-7 relative / absolute);
nonlinear check: f(θ0 + δ) − f(θ0) with δ = 1e-5 on a re-rendered (1) or perturbed (2)
model; the two agree to ~1e-5 relative (second-order remainder).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.accuracy import AccuracyRow, accuracy_model
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm import PLACEMENT_JOINTS
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.render import declared_args
from rcm_pin.rotations import FloatArray

COMPONENTS = ("dx", "dy", "dz", "rx", "ry", "rz")


def outputs(model: pin.Model, data: pin.Data, q_pin: FloatArray) -> FloatArray:
    """[p (3), log(R) (3), c (3)] for a model at Pinocchio configuration q_pin."""
    pin.framesForwardKinematics(model, data, q_pin)
    tool = data.oMf[model.getFrameId("tool")]
    a = data.oMf[model.getFrameId("rcm")].translation
    org = data.oMf[model.getFrameId("working_organ")]
    e = org.rotation[:, 2]
    d = org.translation - a
    c = d - (d @ e) * e
    return np.r_[tool.translation, pin.log3(tool.rotation), c]


def _fd(f: Callable[[float], FloatArray], h: float) -> FloatArray:
    return (f(h) - f(-h)) / (2 * h)


def _value(nominal: Mechanism, param: str) -> float:
    """The nominal value of a xacro argument (given, or the source's default)."""
    if param in nominal.args:
        return float(nominal.args[param])
    if nominal.source is None:
        raise InvalidInputError(f"{nominal.name} has no xacro source for {param!r}")
    return float(declared_args(nominal.source)[param])


def xacro_sensitivity(
    nominal: Mechanism, q: FloatArray, param: str, h: float = 1e-7
) -> tuple[FloatArray, Callable[[float], FloatArray]]:
    """∂[p, logR, c]/∂θ for one xacro parameter (per unit of θ), and f(δ) − f(0).

    Returns:
        (first-order derivative (9,), function δ -> nonlinear change (9,)).
    """
    valid = accuracy_model(nominal).parameters(nominal)
    if param not in valid or nominal.rebuild is None:
        raise InvalidInputError(
            f"xacro parameter {param!r} not in {nominal.name}; valid: {', '.join(valid)}"
        )
    x0 = _value(nominal, param)
    qp = nominal.to_pin(q)
    f0 = outputs(nominal.model, nominal.data, qp)
    rebuild = nominal.rebuild

    def change(delta: float) -> FloatArray:
        m = rebuild(**{param: repr(x0 + delta)})
        return outputs(m.model, m.data, qp) - f0

    return _fd(change, h * max(1.0, abs(x0))), change


def placement_sensitivity(
    mech: Mechanism, q: FloatArray, joint: str, component: int, h: float = 1e-7
) -> tuple[FloatArray, Callable[[float], FloatArray]]:
    """∂[p, logR, c]/∂δ for one component of a joint-placement error (see module doc)."""
    if not mech.model.existJointName(joint):
        raise InvalidInputError(f"joint {joint!r} not in {mech.name}; valid: {PLACEMENT_JOINTS}")
    jid = mech.model.getJointId(joint)
    qp = mech.to_pin(q)
    f0 = outputs(mech.model, mech.data, qp)
    model = mech.model.copy()
    data = model.createData()
    M0 = mech.model.jointPlacements[jid].copy()

    def change(delta: float) -> FloatArray:
        xi = np.zeros(6)
        xi[component] = delta
        model.jointPlacements[jid] = M0 * pin.exp6(xi)
        return outputs(model, data, qp) - f0

    return _fd(change, h), change


def report(mech: Mechanism, q: FloatArray) -> dict[str, Any]:
    """Sensitivity table: tool-position and RCM-offset change per unit error, and per
    0.1 mm (lengths) / 0.1° (angles) / 0.1 % (ratios: tooth counts, diameters)."""
    params = accuracy_model(mech).parameters(mech)
    if mech.rcm is None or not params:
        raise InvalidInputError(
            f"the RCM accuracy table needs an RCM mechanism, got {mech.name}; valid: "
            "rcm_bevel, rcm_bevel_4dof, rcm_belt"
        )
    q = mech.check_q(q)
    rows: list[dict[str, Any]] = []
    for param in params:
        d, _ = xacro_sensitivity(mech, q, param)
        ratio = param[0] in "zd"
        x0 = _value(mech, param)
        unit = 1e-3 * x0 if ratio else 1e-4  # 0.1 % of a ratio parameter, 0.1 mm of a length
        rows.append(_row(f"xacro {param}", "ratio 0.1 %" if ratio else "length 0.1 mm", d, unit))
    for joint in PLACEMENT_JOINTS:
        for k, comp in enumerate(COMPONENTS):
            d, _ = placement_sensitivity(mech, q, joint, k)
            unit = 1e-4 if k < 3 else np.deg2rad(0.1)
            kind = "length 0.1 mm" if k < 3 else "angle 0.1 deg"
            rows.append(_row(f"{joint} placement {comp}", kind, d, unit))
    rows.sort(key=lambda r: -float(r["rcm_per_error"]))
    return {"mechanism": mech.name, "q": q, "rows": rows}


def _row(parameter: str, kind: str, d: FloatArray, unit: float) -> dict[str, Any]:
    return {
        "parameter": parameter,
        "kind": kind,
        "error_unit": unit,
        "d_position": d[:3],
        "d_rotation": d[3:6],
        "d_rcm": d[6:],
        "tool_per_error": float(np.linalg.norm(d[:3]) * unit),
        "rcm_per_error": float(np.linalg.norm(d[6:]) * unit),
    }


def row(r: Mapping[str, Any]) -> AccuracyRow:
    """A row of :func:`report` in the CLI's one row shape (first order: tool, RCM line)."""
    return AccuracyRow(r["parameter"], r["kind"], r["tool_per_error"], None, r["rcm_per_error"], r)


__all__ = [
    "COMPONENTS",
    "outputs",
    "placement_sensitivity",
    "report",
    "row",
    "xacro_sensitivity",
]
