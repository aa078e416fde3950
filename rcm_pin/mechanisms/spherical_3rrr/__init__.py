"""The spherical 3-RRR parallel mechanism of paper 004 (Fig. 5): the family.

* :mod:`.closed_form`: the loop equations F_i = w_i·v_i − cos θ_i2, the inverse problem in
  tan(φ/2) form (8 working modes), the Agile Eye's direct problem (4 assembly modes), A, B,
  and the proof that the Agile Eye has no type-2 pose off its type-1 set;
* :mod:`.direct`: the direct problem of any design, a trigonometric polynomial of degree 4
  in one passive angle of leg 1 (at most 8 assembly modes);
* :mod:`.paper`: paper 004's tan φ equations F1..F3 (F1 corrected) and A, B from them;
* :mod:`.maps`, :mod:`.workspace`, :mod:`.plots`: singularity maps in tilt-and-torsion
  angles, the six singular curves, the largest singularity-free tilt cone (two routes);
* :mod:`.accuracy`: paper 004's linear accuracy theory (the δα Cramer misprints) beside the
  nonlinear recomputation (the ``accuracy`` hook).

Working modes are labelled by the sign of u_i·(w_i × v_i) of each leg, ``+++`` … ``---``
(index 4 s_1 + 2 s_2 + s_3, s_i = 0 for ``+``); ``home`` (R = I, φ = 0) is ``+++``.

Paper 004's position equations (R = Rz(γ)Ry(β)Rx(α)) are tan φ_i of the orthogonal design;
they fix the legs as u_i = e_i, w_i0 = e_{i+1}, v_i0 = e_{i+2} (the xacro's defaults):

* F2 = sin β/(cos γ cos β) − tg φ21 = 0 is tg φ2 = −R_20/R_00 (w_2 = Rot(y, φ_2) z ⊥ R x),
  right as printed;
* F3 = (cos γ sin β sin α − cos α sin γ)/(cos α cos γ + sin α sin β sin γ) + tg φ31 = 0 is
  tg φ3 = −R_01/R_11 (w_3 = Rot(z, φ_3) x ⊥ R y), right as printed;
* F1 as printed, tg φ11 − (cos γ sin γ sin β + cos γ sin α)/(cos α cos β), is a misprint:
  w_1 = Rot(x, φ_1) y ⊥ R z gives tg φ11 = −R_12/R_22, i.e.
  **F1 = tg φ11 − (cos γ sin α − sin γ sin β cos α)/(cos α cos β)**. The denominator
  cos α cos β = R_22 is right and the F2/F3 pattern (column j of R, rows j+2 over j) fixes
  the numerator R_12 = sin γ sin β cos α − cos γ sin α: the printed first term has cos γ
  for cos α and the wrong sign. Printed minus corrected is
  sin γ sin β (cos γ + cos α)/(cos α cos β): zero for β = 0 or γ = 0 (R = Rz(γ)Rx(α) or
  Ry(β)Rx(α)), so such checks do not reveal the misprint; α = 0.3, β = 0.4,
  γ = 0.5 gives tg φ11 = 0.0920 (corrected) against 0.4809 (printed).
  :func:`.paper.tan_phi` evaluates both; the tests check the corrected F1..F3 against the
  Pinocchio loop closures, and :mod:`.paper`'s A, B from their derivatives (the third
  route) against Pinocchio's output Jacobian.

A of the paper is written on (α, β, γ) but multiplied by ω: here A multiplies the world
angular velocity ω (rows (v_i × w_i)ᵀ), B = diag(u_i·(w_i × v_i)).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.accuracy import AccuracyModel, AccuracyReport, AccuracyRow
from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.analysis.singularity_model import ABMatrices, NumericSingularity
from rcm_pin.analysis.workspace import WorkspaceModel
from rcm_pin.errors import SingularConfigurationError, UnreachablePoseError
from rcm_pin.interfaces.design import DesignMetric, MetricSource
from rcm_pin.lazy import lazy_modules
from rcm_pin.mechanisms.spherical_3rrr import accuracy, direct
from rcm_pin.mechanisms.spherical_3rrr import closed_form as sc
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.rotations import matrix_to_rpy

#: Size of each error variable of :meth:`Spherical3RRRAccuracy.report` [rad].
ACCURACY_ERROR = float(np.radians(0.5))
#: Working-mode labels in index order.
MODES = tuple(f"{w:03b}".replace("0", "+").replace("1", "-") for w in range(8))


def geometry(mech: Mechanism) -> sc.GeometrySpherical:
    """The closed-form geometry of a loaded spherical 3-RRR (from its sidecar parameters)."""
    return sc.GeometrySpherical.from_params(mech.require_loops().params)


def full_q(mech: Mechanism, R: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Mechanism coordinates (n,) [rad] of orientation R with drives φ."""
    angles = dict(zip(sc.JOINTS, sc.joint_angles(geometry(mech), R, phi), strict=True))
    return np.array([angles[j] for j in mech.joint_names])


def pose_and_drives(mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R (3, 3), φ (3,)) of a closed configuration."""
    return mech.output_value(q).reshape(3, 3), np.asarray(q)[mech.require_loops().drive_q]


def normalised_ab(
    g: sc.GeometrySpherical, R: np.ndarray, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """A with row i over sin θ_i2 and B_ii over sin θ_i1 sin θ_i2: unit rows, |B_ii| ≤ 1."""
    a_mat, b_mat = sc.ab_matrices(g, R, phi)
    return a_mat / np.sin(g.t2)[:, None], b_mat / (np.sin(g.t1) * np.sin(g.t2))[:, None]


class Spherical3RRRPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Eight working modes (two roots of each leg's tan(φ/2) quadratic)."""
        if output.coords != ("rotation",):
            return super().inverse(mech, target, output)
        g, R = geometry(mech), np.asarray(target, dtype=float).reshape(3, 3)
        _, delta, rho = sc.leg_roots(g, R)
        if np.any(rho < sc.DELTA_TOL):
            legs = ", ".join(str(i + 1) for i in np.flatnonzero(rho < sc.DELTA_TOL))
            raise SingularConfigurationError(
                f"{mech.name}: the platform axis of leg {legs} lies on its base axis, every "
                "drive angle closes the leg (type 1); valid: an orientation with v_i not "
                "along u_i"
            )
        if np.any(delta < -sc.DELTA_TOL):
            legs = ", ".join(str(i + 1) for i in np.flatnonzero(delta < -sc.DELTA_TOL))
            raise UnreachablePoseError(
                f"{mech.name}: orientation out of reach of leg {legs} (the cone of w_i about "
                "u_i misses the cone about v_i, Δ < 0); valid: orientations with "
                "|γ_i − θ_i1| ≤ θ_i2 ≤ min(γ_i + θ_i1, 2π − γ_i − θ_i1), γ_i = angle(u_i, v_i)"
            )
        phis = sc.inverse_position(g, R)
        return Branches.of(mech, [Branch(full_q(mech, R, phis[w]), MODES[w]) for w in range(8)])

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """Every assembly mode: the Agile Eye's closed form (4), else the real roots of the
        degree-4 trigonometric polynomial of :mod:`.direct` (at most 8)."""
        g = geometry(mech)
        phi = np.asarray(drives, dtype=float)
        rs = sc.direct_position(g, phi) if g.agile_eye else direct.direct_position(g, phi)
        return Assemblies.of([full_q(mech, R, phi) for R in rs])

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """``+++`` … ``---``."""
        return MODES


class Spherical3RRRWorkspace(WorkspaceModel):
    """Reachable share of ``samples`` (≤ 20 000) random orientations; for the Agile Eye the
    largest singularity-free tilt cone about the symmetry axis [deg] for torsion half-ranges
    0°, 30°, …, 180° (:mod:`.workspace`, the curve route); the singularity maps."""

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        from rcm_pin.mechanisms.spherical_3rrr import maps, workspace
        from rcm_pin.rotations import random_rotations

        g = geometry(mech)
        n_rot = 20_000 if samples is None else min(samples, 20_000)
        rots = random_rotations(np.random.default_rng(seed), n_rot)
        reach = float(np.mean(np.all(sc.leg_roots(g, rots)[1] >= -sc.DELTA_TOL, axis=1)))
        out: dict[str, Any] = {"orientations": n_rot, "reachable_share": reach}
        if g.agile_eye:
            axis = maps.symmetry_axis(g)
            out["symmetry_axis"] = axis
            for sig in range(0, 181, 30):
                cone = workspace.cone_from_curves(g, axis, np.radians(sig))
                out[f"cone_deg_torsion_{sig}"] = float(np.degrees(cone)) if cone > 1e-9 else 0.0
        return out

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """The singularity maps (tilt, azimuth × torsion) of working mode ``mode``."""
        from rcm_pin.mechanisms.spherical_3rrr import plots

        return plots.maps_figure(geometry(mech), Path(path), mode=int(options.get("mode") or 0))


class Spherical3RRRMetrics(MetricSource):
    """Regular share of SO(3) and conditioning of a design (:mod:`.design`)."""

    def metrics(self) -> dict[str, DesignMetric]:
        from rcm_pin.mechanisms.spherical_3rrr.design import METRICS

        return dict(METRICS)


class Spherical3RRRSingularity(NumericSingularity):
    """A/B of the loop equations (no named causes, the numeric map)."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """Normalised A and B of the loop equations (:func:`normalised_ab`)."""
        return ABMatrices(*normalised_ab(geometry(mech), *pose_and_drives(mech, q)), paper=True)


class Spherical3RRRAccuracy(AccuracyModel):
    """Paper 004's linear theory (Cramer) beside the nonlinear re-solve (:mod:`.accuracy`)."""

    def parameters(self, mech: Mechanism) -> tuple[str, ...]:
        """The link angles θ_i1, θ_i2 (xacro arguments, the paper's error variables)."""
        return tuple(p for p in accuracy.PARAMETERS if p.startswith("theta"))

    def report(self, mech: Mechanism, q: np.ndarray) -> AccuracyReport:
        """Linear (Cramer) vs nonlinear output errors for 0.5° in each link angle and each
        drive angle, drives locked, at the closed configuration q (:mod:`.accuracy`)."""
        R, phi = pose_and_drives(mech, mech.check_q(q))
        x = np.array(matrix_to_rpy(R))
        rows = accuracy.table(geometry(mech), x, phi, ACCURACY_ERROR)
        table = {"mechanism": mech.name, "q": q, "angles": x, "error": ACCURACY_ERROR, "rows": rows}
        return AccuracyReport.of(table, AccuracyRow.of_output)


class Spherical3RRRFamily(Family):
    """Hooks of the spherical 3-RRR (module docstring)."""

    name = "spherical_3rrr"
    description = "spherical 3-RRR parallel mechanisms, Agile Eye (paper 004)"
    closed = True
    capabilities = (
        Spherical3RRRPosition(),
        Spherical3RRRWorkspace(),
        Spherical3RRRMetrics(),
        Spherical3RRRSingularity(),
        Spherical3RRRAccuracy(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: R = I, φ = 0, working mode ``+++`` (every joint angle 0)."""
        return {"home": full_q(mech, np.eye(3), np.zeros(3))}


FAMILY = Spherical3RRRFamily()

__all__ = [
    "ACCURACY_ERROR",
    "FAMILY",
    "MODES",
    "Spherical3RRRFamily",
    "full_q",
    "geometry",
    "normalised_ab",
    "pose_and_drives",
]

# Each module of the family is an attribute of the package, imported on first access
# (``from rcm_pin.mechanisms import <family>`` is the public entry, docs/api.md).
__getattr__, __dir__ = lazy_modules(
    __name__, ("accuracy", "closed_form", "design", "direct", "maps", "paper", "plots", "workspace")
)
