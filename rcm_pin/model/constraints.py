"""The closures as Pinocchio constraints, and the planar test of a tree.

:func:`constraint_models` turns each closure into a ``pin.RigidConstraintModel``
(CONTACT_3D / CONTACT_6D in the LOCAL frame of a), the second route to the closure
Jacobian (:func:`pin_constraint_jacobian`) and the input of ``pin.constraintDynamics``.
:func:`plane_normal` tells whether a tree moves in one plane.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.model.loops import LOCAL, Loops


def constraint_models(model: pin.Model, loops: Loops) -> list[pin.RigidConstraintModel]:
    """The closures as ``pin.RigidConstraintModel`` s (CONTACT_3D / CONTACT_6D, LOCAL)."""
    out = []
    for c in loops.closures:
        fa, fb = model.frames[c.frame_a_id], model.frames[c.frame_b_id]
        kind = pin.ContactType.CONTACT_3D if c.kind == "3d" else pin.ContactType.CONTACT_6D
        cm = pin.RigidConstraintModel(
            kind, model, fa.parentJoint, fa.placement, fb.parentJoint, fb.placement, LOCAL
        )
        cm.name = f"{c.frame_a}__{c.frame_b}"
        out.append(cm)
    return out


def pin_constraint_jacobian(model: pin.Model, loops: Loops, q: np.ndarray) -> np.ndarray:
    """Kept rows of ``pin.getConstraintsJacobian`` (second route to J_c, no-mimic models)."""
    data = model.createData()
    cms = pin.StdVec_RigidConstraintModel()
    cds = pin.StdVec_RigidConstraintData()
    for cm in constraint_models(model, loops):
        cms.append(cm)
        cds.append(cm.createData())
    pin.computeJointJacobians(model, data, q)
    for cm, cd in zip(cms, cds, strict=True):
        cm.calc(model, data, cd)
    jac = pin.getConstraintsJacobian(model, data, cms, cds)
    offsets = np.cumsum([0] + [3 if c.kind == "3d" else 6 for c in loops.closures])
    rows = [offsets[i] + r for i, c in enumerate(loops.closures) for r in c.rows]
    return np.asarray(jac)[rows]


def plane_normal(model: pin.Model) -> np.ndarray | None:
    """The common axis of a planar tree (every joint revolute about it or prismatic across
    it, at the neutral configuration), else None."""
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    axes, slides = [], []
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.nv != 1:
            return None
        # reshape: a one-column Jacobian (a model with nv = 1) comes back 1-D
        jac = np.asarray(pin.getJointJacobian(model, data, j, pin.WORLD)).reshape(6, model.nv)
        col = jac[:, jm.idx_v]
        if np.linalg.norm(col[3:]) > 1e-12:
            axes.append(col[3:])  # revolute: its axis
        else:
            slides.append(col[:3])  # prismatic: its direction
    if not axes:
        return None
    n = axes[0] / np.linalg.norm(axes[0])
    parallel = all(abs(abs(a @ n) - np.linalg.norm(a)) < 1e-12 for a in axes)
    across = all(abs(s @ n) < 1e-12 for s in slides)
    return n if parallel and across else None


__all__ = ["constraint_models", "pin_constraint_jacobian", "plane_normal"]
