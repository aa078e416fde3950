"""The planar five-bar RR-RR (paper 004 Fig. 13) with main and extra drives: the family.

Geometry (``xacro/five_bar.urdf.xacro``)::

    A_1 = (−d/2, 0), A_2 = (d/2, 0)                       base pairs (main drives q_1, q_2)
    B_i = A_i + l1_i (cos q_i, sin q_i)                    elbows (extra drives θ_i, relative)
    F_i(P, q_i) = |P − B_i|² − l2_i² = 0                   loop equations, P = (x, y) [m]

Main drives (q_1, q_2), Angeles–Gosselin A ẋ = −B q̇ with u_i = P − B_i::

    A = 2 [u_1ᵀ; u_2ᵀ],  B = diag(−2 (B_i − A_i) × u_i)     [m², m²/rad]
    type 2 (det A = 0): B_1, P, B_2 aligned;  type 1 (det B = 0): A_i, B_i, P aligned.

Extra drives (elbow angles θ_i): |P − A_i|² = ρ_i², ρ_i² = l1_i² + l2_i² + 2 l1_i l2_i cos θ_i::

    A' = 2 [(P − A_1)ᵀ; (P − A_2)ᵀ]; type 2 of the extra drives: A_1, P, A_2 aligned (P on
    the base line), far from the main drives' type-2 curve.

Working modes: elbow sign σ_i per leg, 4 modes; assembly modes: the two intersections of the
circles (B_1, l2_1) and (B_2, l2_2).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.analysis.singularity_model import ABMatrices, DetMap, NumericSingularity
from rcm_pin.analysis.workspace import WorkspaceModel
from rcm_pin.control.capabilities import DefaultScenarios
from rcm_pin.control.references import QuinticPath
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.geometry import circle_points
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle as wrap


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@dataclass(frozen=True)
class GeometryFiveBar:
    """Base pivots A (2, 2), proximal l1 (2,), distal l2 (2,) [m]."""

    base: np.ndarray
    l1: np.ndarray
    l2: np.ndarray

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> GeometryFiveBar:
        """From the sidecar ``params``."""
        d = p["base_distance"]
        return cls(
            base=np.array([[-d / 2, 0.0], [d / 2, 0.0]]),
            l1=np.array([p["proximal_1"], p["proximal_2"]]),
            l2=np.array([p["distal_1"], p["distal_2"]]),
        )

    def elbows(self, q: np.ndarray) -> np.ndarray:
        """B (..., 2, 2) for main drive angles q (..., 2) [rad]."""
        q = np.asarray(q, dtype=float)
        return self.base + self.l1[:, None] * np.stack([np.cos(q), np.sin(q)], axis=-1)


def loop_equations(g: GeometryFiveBar, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """F_i = |P − B_i|² − l2_i² (..., 2) [m²]."""
    u = np.asarray(p)[..., None, :] - g.elbows(q)
    return np.sum(u * u, axis=-1) - g.l2**2


def ab_matrices(g: GeometryFiveBar, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Main-drive A (..., 2, 2) and B (..., 2, 2) (module docstring)."""
    bb = g.elbows(q)
    u = np.asarray(p)[..., None, :] - bb
    b_diag = -2.0 * _cross(bb - g.base, u)
    return 2.0 * u, b_diag[..., :, None] * np.eye(2)


def extra_a_matrix(g: GeometryFiveBar, p: np.ndarray) -> np.ndarray:
    """A' (..., 2, 2) of the extra (elbow) drives: rows 2 (P − A_i)ᵀ [m²]."""
    return 2.0 * (np.asarray(p)[..., None, :] - g.base)


def type2_measure(g: GeometryFiveBar, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """|sin| of the angle between the distal links B_1P and B_2P (0 on the type-2 curve)."""
    u = np.asarray(p)[..., None, :] - g.elbows(q)
    return np.abs(_cross(u[..., 0, :], u[..., 1, :])) / (g.l2[0] * g.l2[1])


def extra_type2_measure(g: GeometryFiveBar, p: np.ndarray) -> np.ndarray:
    """|sin| of the angle A_1 P A_2 (0 where the extra drives are singular)."""
    u = np.asarray(p)[..., None, :] - g.base
    n = np.linalg.norm(u, axis=-1)
    return np.abs(_cross(u[..., 0, :], u[..., 1, :])) / (n[..., 0] * n[..., 1])


def inverse_position(g: GeometryFiveBar, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Working modes (..., 4, 2) of main drive angles for P (..., 2); mode w = 2 s_1 + s_2.

    q_i = atan2(P − A_i) + σ_i acos((|A_iP|² + l1_i² − l2_i²)/(2 l1_i |A_iP|)), σ_i = 1 − 2 s_i.

    Returns:
        (q [rad] with NaN where unreachable, reachable (...,) bool).
    """
    d = np.asarray(p, dtype=float)[..., None, :] - g.base
    dist = np.linalg.norm(d, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_g = (dist**2 + g.l1**2 - g.l2**2) / (2.0 * g.l1 * dist)
    reach = np.all(np.abs(cos_g) <= 1.0, axis=-1)
    gam = np.where(np.abs(cos_g) <= 1.0, np.arccos(np.clip(cos_g, -1, 1)), np.nan)
    theta = np.arctan2(d[..., 1], d[..., 0])
    signs = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]])
    return wrap(theta[..., None, :] + signs * gam[..., None, :]), reach


def full_q(g: GeometryFiveBar, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Pinocchio configuration (A1, B1, A2, B2) (..., 4) [rad] for P and main drives q."""
    u = np.asarray(p)[..., None, :] - g.elbows(q)
    rel = wrap(np.arctan2(u[..., 1], u[..., 0]) - q)
    return np.stack([q[..., 0], rel[..., 0], q[..., 1], rel[..., 1]], axis=-1)


def direct_position(g: GeometryFiveBar, q: np.ndarray) -> np.ndarray:
    """Assembly modes P (N, 2), N ∈ {0, 1, 2}: intersections of circles (B_i, l2_i), P left
    of B_1 → B_2 first."""
    bb = g.elbows(q)
    return np.array(circle_points(bb[0], g.l2[0], bb[1], g.l2[1])).reshape(-1, 2)


# ============================================================================ the family
#: Working-mode labels (elbow signs σ_1 σ_2) in index order w = 2 s_1 + s_2.
MODES = ("++", "+-", "-+", "--")
#: Paper 004's crossing of the main drives' type-2 curve (Figs. 13–14) [m, s].
CROSSING = QuinticPath((0.01, 0.17), (-0.01, 0.02), 1.0)


def geometry(mech: Mechanism) -> GeometryFiveBar:
    """The closed-form geometry of a loaded five-bar (from its sidecar parameters)."""
    return GeometryFiveBar.from_params(mech.require_loops().params)


def point_grid(g: GeometryFiveBar, n: int) -> tuple[np.ndarray, np.ndarray]:
    """An n × n grid covering the reach of both legs [m]."""
    r = float(np.max(g.l1 + g.l2))
    d = float(g.base[1, 0])
    return np.linspace(-r - d, r + d, n), np.linspace(-r, r, n)


class FiveBarPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Four working modes (elbow signs) of the point P."""
        if output.coords != ("x", "y"):
            return super().inverse(mech, target, output)
        g = geometry(mech)
        qs, ok = inverse_position(g, target)
        if not ok:
            raise UnreachablePoseError(
                f"{mech.name}: point {target.tolist()} is outside the workspace (a leg cannot "
                "reach it: |l1 − l2| ≤ |A_i P| ≤ l1 + l2 fails)"
            )
        return Branches.of(mech, [Branch(full_q(g, target, qs[w]), MODES[w]) for w in range(4)])

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """The two intersections of the circles (B_i, l2_i) (main drives only)."""
        if mech.require_loops().drives != ("A1", "A2"):
            return super().direct(mech, drives)  # the extra-drive set: numeric route
        g = geometry(mech)
        return Assemblies.of([full_q(g, p, drives) for p in direct_position(g, drives)])

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """``++``, ``+-``, ``-+``, ``--``."""
        return MODES


class FiveBarScenarios(DefaultScenarios):
    """The crossing of paper 004 Fig. 13 (no stop events: the law switches drives)."""

    def scenarios(self, mech: Mechanism) -> dict[str, Any]:
        """Paper 004 Figs. 13–14: a path across the main drives' type-2 curve, drive
        switching inside σ_min/σ_max(A) < 0.2, torque limit 0.5 N·m (τ_c = 0.03 s)."""
        from rcm_pin.control.computed_torque import Gains
        from rcm_pin.control.scenario import Scenario

        return {
            "crossing": Scenario(
                CROSSING,
                Gains.from_tau_zeta(0.03, 1.0),
                1.3,
                "quintic (0.01, 0.17) -> (-0.01, 0.02) m in 1 s, 0.3 s rest",
                mode=1,
                offset=(0.002, 0.0),
                switching=0.2,
                limit=0.5,
                method="RK45",
                rtol=1e-8,
                atol=1e-10,
                max_step=5e-3,
                samples=None,
            )
        }


class FiveBarWorkspace(WorkspaceModel):
    """The point workspace of P [m²] on an n × n grid; det A / det B over it."""

    options = ("n",)

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        n = int(options.get("n", 121))
        g = geometry(mech)
        x, y = point_grid(g, n)
        ok = inverse_position(g, np.stack(np.meshgrid(x, y), axis=-1))[1]
        cell = float((x[1] - x[0]) * (y[1] - y[0]))
        area = float(ok.sum()) * cell
        return {
            "phi": None,
            "phi_range": None,
            "orientations": 1,
            "grid": n,
            "cell_area": cell,
            "constant_orientation_area": area,
            "total_area": area,
            "reachable_area": area,
        }

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """det A / det B of the main drives over the point workspace (mode ``+-``)."""
        from rcm_pin.analysis.maps import plot_singularity_map, singularity_map

        return plot_singularity_map(
            singularity_map(mech, mode=1, n=int(options.get("n", 121))), path
        )


class FiveBarSingularity(NumericSingularity):
    """A/B of the main drives from the loop equations, and their maps (no named causes)."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """Main-drive A / (2 l2_i) and B / (2 l1_i l2_i) (dimensionless determinants)."""
        g = geometry(mech)
        a_mat, b_mat = ab_matrices(g, mech.output_value(q), q[mech.require_loops().drive_q])
        return ABMatrices(
            a_mat / (2.0 * g.l2[:, None]), b_mat / (2.0 * (g.l1 * g.l2)[:, None]), paper=True
        )

    def workspace_map(self, mech: Mechanism, mode: int, phi: float, n: int) -> DetMap:
        """Normalised det A, det B of the main drives over the point workspace."""
        g = geometry(mech)
        x, y = point_grid(g, n)
        pts = np.stack(np.meshgrid(x, y), axis=-1)
        qs, ok = inverse_position(g, pts)
        a_mat, b_mat = ab_matrices(g, pts, np.nan_to_num(qs[..., mode, :]))
        da = np.linalg.det(a_mat) / (4 * np.prod(g.l2))
        db = np.linalg.det(b_mat) / (4 * np.prod(g.l1) * np.prod(g.l2))
        da[~ok], db[~ok] = np.nan, np.nan
        return DetMap(x, y, da, db, MODES[mode], None)


class FiveBarFamily(Family):
    """Hooks of the five-bar: working and assembly modes, A/B of the main drives."""

    name = "five_bar"
    description = "planar five-bar RR-RR with extra drives (paper 004 Fig. 13)"
    closed = True
    capabilities = (
        FiveBarPosition(),
        FiveBarScenarios(),
        FiveBarWorkspace(),
        FiveBarSingularity(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: P on the symmetry axis at 60 % of the reach, working mode ``++``."""
        from rcm_pin.analysis.position import inverse

        reach = float(
            mech.require_loops().params["proximal_1"] + mech.require_loops().params["distal_1"]
        )
        return {"home": inverse(mech, np.array([0.0, 0.6 * reach])).solutions[0].q}


FAMILY = FiveBarFamily()
