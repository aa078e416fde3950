"""Solver settings of an MJCF export and the inertia floor of massless moving bodies.

MuJoCo keeps an equality (a loop closure, a mimic transmission) as a *soft* constraint: the
constraint acceleration a₁ = J q̈ is pulled towards the reference a_ref = −b (J v) − k r − J̇v
of a spring-damper with time constant τ_c and damping ratio ζ, mixed with the unconstrained
acceleration a₀ through the impedance d (``solimp``): a₁ ≈ d a_ref + (1 − d) a₀. The rule
written into every export:

* ``solimp = (0.9999, 0.9999, 0.001, 0.5, 2)``: d at MuJoCo's maximum, flat in the residual;
* ``solref = (2·dt, 1)``: the stiffest time constant MuJoCo accepts for the timestep
  (τ_c ≥ 2·dt, else it is clamped), critically damped;
* the timestep: the largest of ``DT_CHOICES`` whose predicted drift stays below
  ``drift_tol`` (default 1e-6 m or rad), or the user's timestep.

The prediction model (largest equality residual of a 0.2 s free motion from a closed state
at joint rates up to 1 rad/s) has two terms:

* linear equalities (mimic transmissions): the steady state of the soft constraint,
  ``MIMIC_SAFETY · (1 − d) · a_m · (2·dt)²``, a_m the largest unconstrained acceleration of
  the mimic rows under gravity at home (at least |g|);
* loop closures (nonlinear): the time-stepping error that the spring removes within τ_c,
  ``LOOP_COEFF · a_c · dt²``, a_c the same for the closure rows (at least |g|).

Both fall as dt² (MuJoCo: 16× for 4× smaller dt). The constants bound what MuJoCo measures
on the catalogue and the URDF fixtures (loops: at most 38 · a_c · dt², eye_4dof; mimic:
at most 18 · (1 − d) · a_m · (2·dt)², tests/data/rcm_wrist_arm.urdf), checked by
``tests/test_mujoco_export.py`` and tabulated by ``benchmarks/mujoco_export.py``
(``docs/mujoco.md``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism

#: impedance of every equality: (d₀, d_width, width [m or rad], midpoint, power).
SOLIMP = (0.9999, 0.9999, 0.001, 0.5, 2.0)
#: factor over the soft-constraint steady state of linear (mimic) equalities.
MIMIC_SAFETY = 100.0
#: loop-closure drift coefficient [1]: drift <= LOOP_COEFF · a_c · dt² (module docstring).
LOOP_COEFF = 100.0
#: timesteps tried from the largest [s]: 2, 1, 0.5 × 10⁻³ down to 10⁻⁷.
DT_CHOICES = tuple(m * 10.0**-e for e in range(3, 8) for m in (2.0, 1.0, 0.5))[:-1]
#: default drift tolerance [m or rad].
DRIFT_TOL = 1e-6
#: relative floor of a moving body's mass (× the mechanism's total mass) and inertia
#: (× total mass × length scale²): MuJoCo refuses moving bodies without mass or inertia.
FLOOR = 1e-6


#: below ZERO × the same scales a mass or inertia counts as missing.
ZERO = 1e-12


class InertiaFloorWarning(UserWarning):
    """A moving body whose mass or rotational inertia was raised to the export's floor."""


class InexactExportWarning(UserWarning):
    """Something of the mechanism that MJCF cannot express exactly (the message names it)."""


@dataclass(frozen=True)
class SolverSettings:
    """What an export writes into ``<option>`` and each equality.

    Attributes:
        timestep: dt [s].
        solref: (time constant [s], damping ratio).
        solimp: MuJoCo impedance (d₀, d_width, width, midpoint, power).
        mimic_acceleration: a_m of the mimic rows (0: none) [rad/s² or m/s²].
        loop_acceleration: a_c of the closure rows (0: none) [m/s² or rad/s²].
        predicted_drift: the prediction model's drift at this timestep [m or rad].
        drift_tol: the tolerance the timestep was chosen for [m or rad].
    """

    timestep: float
    solref: tuple[float, float]
    solimp: tuple[float, ...]
    mimic_acceleration: float
    loop_acceleration: float
    predicted_drift: float
    drift_tol: float


def predicted_drift(timestep: float, mimic_acceleration: float, loop_acceleration: float) -> float:
    """max(MIMIC_SAFETY·(1 − d)·a_m·(2·dt)², LOOP_COEFF·a_c·dt²) [m or rad] (module
    docstring)."""
    mimic = MIMIC_SAFETY * (1.0 - SOLIMP[1]) * mimic_acceleration * (2.0 * timestep) ** 2
    return max(mimic, LOOP_COEFF * loop_acceleration * timestep**2)


def free_accelerations(mech: Mechanism) -> tuple[float, float]:
    """(a_m, a_c) [rad/s², m/s²]: max |J M⁻¹ (−g(q))| over the mimic rows (no-mimic model)
    and over the closure world rows (mimic model) at home, each at least |g| (0 where the
    mechanism has no such rows)."""
    full = mech.model_full
    g = float(np.linalg.norm(full.gravity.linear)) or 9.81
    q_pin = mech.to_pin(mech.home)
    out = []
    for model, q, rows in (
        (full, mech.coupling.q_full(q_pin), _mimic_rows(mech)),
        (mech.model, q_pin, _closure_rows(mech, q_pin)),
    ):
        if not len(rows):
            out.append(0.0)
            continue
        data = model.createData()
        m_mat = pin.crba(model, data, q)
        m_mat = np.triu(m_mat) + np.triu(m_mat, 1).T
        acc = np.linalg.lstsq(m_mat, -pin.computeGeneralizedGravity(model, data, q), rcond=None)
        out.append(max(g, float(np.max(np.abs(rows @ acc[0])))))
    return out[0], out[1]


def _closure_rows(mech: Mechanism, q_pin: np.ndarray) -> np.ndarray:
    """World closure Jacobian (m, nv) at q (none for a serial mechanism)."""
    if mech.loops is None:
        return np.zeros((0, mech.model.nv))
    from rcm_pin.dynamics.constrained import world_closure

    return world_closure(mech, q_pin, np.zeros(mech.model.nv))[1]


def _mimic_rows(mech: Mechanism) -> np.ndarray:
    """Rows (n_mimic, nv_full) of the mimic equalities q_m − k q_p = offset."""
    from rcm_pin.model.coupling import mimic_tags

    full = mech.model_full
    rows = []
    for name, (primary, mult, _) in mimic_tags(mech.urdf).items():
        row = np.zeros(full.nv)
        row[full.joints[full.getJointId(name)].idx_v] = 1.0
        row[full.joints[full.getJointId(primary)].idx_v] -= mult
        rows.append(row)
    return np.array(rows).reshape(-1, full.nv)


def choose(
    mech: Mechanism, timestep: float | None = None, drift_tol: float = DRIFT_TOL
) -> SolverSettings:
    """The solver settings of the rule (module docstring).

    Raises:
        InvalidInputError: a timestep or tolerance that is not a positive finite number, or
            a tolerance that needs a timestep below the smallest choice (1e-7 s).
    """
    for name, value in (("timestep", timestep), ("drift_tol", drift_tol)):
        if value is not None and not (np.isfinite(value) and 0 < value < 1e3):
            raise InvalidInputError(f"{name} {value!r}; valid: a positive number below 1000")
    a_m, a_c = free_accelerations(mech)
    if timestep is None:
        fits = [dt for dt in DT_CHOICES if predicted_drift(dt, a_m, a_c) <= drift_tol]
        if not fits:
            raise InvalidInputError(
                f"drift_tol {drift_tol:g} needs a timestep below {DT_CHOICES[-1]:g} s for "
                f"{mech.name}; valid: a tolerance of at least "
                f"{predicted_drift(DT_CHOICES[-1], a_m, a_c):.2g} (or give the timestep)"
            )
        timestep = fits[0]
    return SolverSettings(
        timestep=float(timestep),
        solref=(2.0 * float(timestep), 1.0),
        solimp=SOLIMP,
        mimic_acceleration=a_m,
        loop_acceleration=a_c,
        predicted_drift=predicted_drift(float(timestep), a_m, a_c),
        drift_tol=float(drift_tol),
    )


def floored(mech: Mechanism, warn: bool = True) -> tuple[Mechanism, tuple[str, ...]]:
    """The mechanism with every moving body's mass and principal inertias raised to the
    floor (FLOOR × total mass, FLOOR × total mass × length scale²) where they are below
    ZERO × the same, principal inertias that violate the triangle inequality set to
    their mean, and the joints whose bodies were raised. The same on both Pinocchio
    models, so that the exported file and rcm-pin compute the same dynamics.

    Warns:
        InertiaFloorWarning: naming each raised body, when ``warn``.
    """
    full = mech.model_full
    total = float(sum(full.inertias[j].mass for j in range(1, full.njoints))) or 1.0
    scale = mech.loops.length_scale if mech.loops is not None else _reach(full)
    m_min, i_min = FLOOR * total, FLOOR * total * scale**2
    raised: list[str] = []
    unbalanced: set[str] = set()
    models = []
    for model in (mech.model, mech.model_full):
        model = model.copy()
        for j in range(1, model.njoints):
            inertia = model.inertias[j]
            eig = np.linalg.eigvalsh(inertia.inertia)
            if 2 * eig.max() > eig.sum() * (1 + 1e-12):  # A + B < C: MuJoCo refuses it
                unbalanced.add(model.names[j])
                inertia = pin.Inertia(inertia.mass, inertia.lever, eig.mean() * np.eye(3))
                model.inertias[j] = inertia
            if inertia.mass > ZERO * total and eig.min() > ZERO * total * scale**2:
                continue
            rot = inertia.inertia + max(0.0, i_min - eig.min()) * np.eye(3)
            model.inertias[j] = pin.Inertia(max(inertia.mass, m_min), inertia.lever, rot)
            if model is not mech.model and model.names[j] not in raised:
                raised.append(model.names[j])
        models.append(model)
    if raised and warn:
        warnings.warn(
            f"{mech.name}: moving bodies {', '.join(raised)} have no mass or inertia, which "
            f"MuJoCo refuses; raised to mass {m_min:.3g} kg and principal inertia "
            f"{i_min:.3g} kg·m² (rcm-pin's floor, docs/mujoco.md)",
            InertiaFloorWarning,
            stacklevel=3,
        )
    if unbalanced and warn:
        warnings.warn(
            f"{mech.name}: bodies {', '.join(sorted(unbalanced))} have principal inertias "
            "that violate A + B >= C, which MuJoCo refuses; set to their mean (as MuJoCo's "
            "balanceinertia does)",
            InertiaFloorWarning,
            stacklevel=3,
        )
    return mech.with_models(models[0], models[1]), tuple(raised)


def _reach(model: pin.Model) -> float:
    """Largest joint-origin distance from the base at the neutral pose [m] (at least 0.1)."""
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    return max([0.1, *(float(np.linalg.norm(m.translation)) for m in data.oMi)])


__all__ = [
    "DRIFT_TOL",
    "FLOOR",
    "LOOP_COEFF",
    "MIMIC_SAFETY",
    "SOLIMP",
    "InertiaFloorWarning",
    "InexactExportWarning",
    "SolverSettings",
    "choose",
    "floored",
    "free_accelerations",
    "predicted_drift",
]
