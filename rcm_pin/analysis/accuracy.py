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
for the chosen error size δ; their relative difference is the linear theory's error.

This is the default :class:`PlacementAccuracy` of the :class:`AccuracyModel` capability:
:func:`accuracy_model` returns the family's model (its own table, e.g. design (xacro)
parameters, :mod:`rcm_pin.mechanisms.rcm.accuracy`) or the default, so ``rcm-pin
accuracy`` has one path and prints one row shape (:class:`AccuracyRow`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
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


@dataclass(frozen=True)
class AccuracyRow:
    """One error variable's effect on the outputs: the one row shape ``rcm-pin accuracy``
    prints; its JSON keys are each table's own (``fields``).

    Attributes:
        variable: the error variable (a joint placement, a link, a design parameter).
        kind: its component or kind (``dx``, ``θ``, ``length 0.1 mm``, ...).
        output: the output change for the error, first order [m, rad].
        nonlinear: the nonlinear change (None: a first-order table, which gives ``rcm``).
        rcm: the RCM line's change for the error [m] (None: not in the table).
        fields: the row as the table writes it (the JSON keys).
    """

    variable: str
    kind: str
    output: float
    nonlinear: float | None
    rcm: float | None
    fields: Mapping[str, Any] = field(repr=False)

    @classmethod
    def of_output(cls, row: Mapping[str, Any]) -> AccuracyRow:
        """A linear-vs-nonlinear row (keys ``joint``, ``component``, ``linear_output``,
        ``nonlinear_output``)."""
        return cls(
            row["joint"],
            row["component"],
            row["linear_output"],
            row["nonlinear_output"],
            row.get("linear_rcm"),
            row,
        )

    def line(self) -> str:
        """The CLI's text line (first-order tables: the tool and RCM-line changes)."""
        if self.nonlinear is None:
            return (
                f"{self.variable:<26} {self.kind:<14} tool {self.output:.3g} m, "
                f"RCM line {self.rcm or 0.0:.3g} m"
            )
        return (
            f"{self.variable:<12} {self.kind:<3} output {self.output:.3g} "
            f"(nonlinear {self.nonlinear:.3g})"
        )


@dataclass(frozen=True)
class AccuracyReport:
    """An accuracy table at one configuration.

    Attributes:
        mechanism: the mechanism's name.
        q: the configuration (n,).
        rows: the error variables' rows, largest effect first.
        extra: the table's other JSON keys (e.g. the point, det A), in their order.
    """

    mechanism: str
    q: np.ndarray
    rows: tuple[AccuracyRow, ...]
    extra: Mapping[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def of(
        cls, table: Mapping[str, Any], row: Callable[[Mapping[str, Any]], AccuracyRow]
    ) -> AccuracyReport:
        """From a ``{"mechanism", "q", ..., "rows"}`` table, each row read by ``row``."""
        extra = {k: v for k, v in table.items() if k not in ("mechanism", "q", "rows")}
        rows = tuple(row(r) for r in table["rows"])
        return cls(table["mechanism"], table["q"], rows, extra)

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``rcm-pin accuracy`` (``mechanism``, ``q``, the extra keys, ``rows``)."""
        return {
            "mechanism": self.mechanism,
            "q": self.q,
            **self.extra,
            "rows": [dict(r.fields) for r in self.rows],
        }

    def lines(self) -> list[str]:
        """The CLI's text, one line per row."""
        return [r.line() for r in self.rows]


class AccuracyModel(ABC):
    """A family's accuracy table and its design-error variables."""

    @abstractmethod
    def parameters(self, mech: Mechanism) -> tuple[str, ...]:
        """xacro arguments that enter the kinematics (design-error variables)."""

    @abstractmethod
    def report(self, mech: Mechanism, q: np.ndarray) -> AccuracyReport:
        """The accuracy table at q (closed: a closed configuration, drives locked)."""


class PlacementAccuracy(AccuracyModel):
    """The default: no design parameters; every joint placement's sensitivity
    (:func:`sensitivities`)."""

    def parameters(self, mech: Mechanism) -> tuple[str, ...]:
        return ()

    def report(self, mech: Mechanism, q: np.ndarray) -> AccuracyReport:
        return AccuracyReport.of(sensitivities(mech, q), AccuracyRow.of_output)


PLACEMENT_ACCURACY = PlacementAccuracy()


def accuracy_model(mech: Mechanism) -> AccuracyModel:
    """The family's :class:`AccuracyModel`, else :class:`PlacementAccuracy`."""
    return mech.family.capability(AccuracyModel) or PLACEMENT_ACCURACY  # type: ignore[type-abstract]


__all__ = [
    "COMPONENTS",
    "AccuracyModel",
    "AccuracyReport",
    "AccuracyRow",
    "PlacementAccuracy",
    "accuracy_model",
    "cramer",
    "placement_change",
    "sensitivities",
]
