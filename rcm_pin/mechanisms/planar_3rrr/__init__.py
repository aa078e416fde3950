"""The planar 3-RRR parallel mechanism of paper 004 (Fig. 1): the family.

* :mod:`.closed_form`: the loop equations F1..F3 with the paper's misprints restored,
  A and B (Angeles–Gosselin), every working mode and the sextic of the assembly modes;
* :mod:`.workspace`: constant- and total-orientation workspaces, singular curves;
* :mod:`.plots`: the workspace figure.

Working modes are labelled by the elbow signs σ_i of the three legs, ``+++`` … ``---``
(index w = 4 s_1 + 2 s_2 + s_3, s_i = 0 for σ_i = +1).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.analysis.singularity_model import ABMatrices, DetMap, NumericSingularity
from rcm_pin.analysis.workspace import WorkspaceModel
from rcm_pin.control.capabilities import DefaultScenarios
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.interfaces.design import DesignMetric, MetricSource
from rcm_pin.lazy import lazy_modules
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Most (x, y, φ) inverse problems of one workspace summary (about 10 s of work).
MAX_EVALUATIONS = 10_000_000
#: Working-mode labels in index order.
MODES = tuple(f"{w:03b}".replace("0", "+").replace("1", "-") for w in range(8))


def geometry(mech: Mechanism) -> p3.Geometry3RRR:
    """The closed-form geometry of a loaded 3-RRR (from its sidecar parameters)."""
    return p3.Geometry3RRR.from_params(mech.require_loops().params)


def _pose_and_drives(mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return mech.output_value(q), q[mech.require_loops().drive_q]


def normalised_ab(
    g: p3.Geometry3RRR, pose: np.ndarray, drives: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """A / (2 l2_i rows, r_p on the φ column) and B / (2 l1_i l2_i): dimensionless, so
    det A_n = det A / (8 l2³ r_p) and det B_n = det B / (8 l1³ l2³)."""
    a_mat, b_mat = p3.ab_matrices(g, pose, drives)
    a_n = a_mat / (2.0 * g.l2[..., :, None]) * np.array([1.0, 1.0, 1.0 / g.rp])
    b_n = b_mat / (2.0 * (g.l1 * g.l2)[..., :, None])
    return a_n, b_n


class Planar3RRRPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Eight working modes (elbow signs) from the loop equations."""
        if output.coords != ("x", "y", "rz"):
            return super().inverse(mech, target, output)
        g = geometry(mech)
        qs, ok = p3.inverse_position(g, target)
        if not ok:
            raise UnreachablePoseError(
                f"{mech.name}: pose {target.tolist()} is outside the workspace (a leg cannot "
                "reach its platform point: |l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 fails)"
            )
        return Branches.of(mech, [Branch(p3.full_q(g, target, qs[w]), MODES[w]) for w in range(8)])

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """Every assembly mode: real roots of the sextic in φ."""
        g = geometry(mech)
        return Assemblies.of([p3.full_q(g, pose, drives) for pose in p3.direct_position(g, drives)])

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """``+++`` … ``---``."""
        return MODES


class Planar3RRRScenarios(DefaultScenarios):
    """Paper 004's platform circle (no stop events)."""

    def scenarios(self, mech: Mechanism) -> dict[str, Any]:
        """Paper 004's control law on a platform circle with a φ oscillation (τ = 0.05 s)."""
        from rcm_pin.control.computed_torque import Gains
        from rcm_pin.control.references import CircleWithAngle
        from rcm_pin.control.scenario import Scenario

        return {
            "circle": Scenario(
                CircleWithAngle(),
                Gains.from_tau_zeta(0.05, 1.0),
                1.0,
                "circle r = 0.03 m about (0.02, 0.01) m, φ ± 0.1 rad, 1 Hz",
                mode="+++",
                offset=(0.002, -0.001, 0.01),
                rtol=1e-11,
                atol=1e-13,
                samples=201,
            )
        }


class Planar3RRRWorkspace(WorkspaceModel):
    """Constant-orientation, total and reachable areas [m²] on an n × n grid; the figure."""

    options = ("n", "phi", "phi_range")

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        from rcm_pin.mechanisms.planar_3rrr import workspace as ws

        phi = float(options.get("phi", 0.0))
        phi_range: tuple[float, float] = options.get("phi_range") or (-np.pi, np.pi)
        lo, hi = float(phi_range[0]), float(phi_range[1])
        step, n = float(options.get("phi_step", 2.0 * np.pi / 180.0)), int(options.get("n", 121))
        if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi <= lo + 2.0 * np.pi + 1e-9):
            raise InvalidInputError(
                f"phi range {lo:g},{hi:g}; valid: finite lo <= hi within one turn (hi − lo <= "
                "2π) [rad]"
            )
        if not (np.isfinite(step) and step > 0.0):
            raise InvalidInputError(f"phi step {step:g}; valid: > 0 [rad]")
        count_phi = int(np.floor((hi - lo) / step + 1e-9)) + 1  # = len(phis) below
        if n * n * count_phi > MAX_EVALUATIONS:
            raise InvalidInputError(
                f"a {n} x {n} grid at {count_phi} orientations is {n * n * count_phi:.3g} inverse "
                f"problems; valid: at most {MAX_EVALUATIONS:.0e} (a smaller --n or a coarser "
                "phi step)"
            )
        g = geometry(mech)
        grid = ws.Grid.around(g, n)
        cell = float((grid.x[1] - grid.x[0]) * (grid.y[1] - grid.y[0]))
        phis = np.arange(lo, hi + 1e-12, step) if hi > lo else np.array([lo])
        count = ws.orientation_count(g, grid, phis)
        w = ws.constant_orientation(g, grid, phi)
        return {
            "phi": phi,
            "phi_range": [float(lo), float(hi)],
            "orientations": len(phis),
            "grid": n,
            "cell_area": cell,
            "constant_orientation_area": float(w.sum()) * cell,
            "total_area": float((count == len(phis)).sum()) * cell,
            "reachable_area": float((count > 0).sum()) * cell,
        }

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """Workspace with type-1/type-2 curves and the total-orientation map."""
        from rcm_pin.mechanisms.planar_3rrr.plots import workspace_figure

        return workspace_figure(
            geometry(mech), Path(path), float(options.get("phi", 0.0)), n=int(options.get("n", 121))
        )


class Planar3RRRMetrics(MetricSource):
    """Regular workspace area and conditioning of a design (:mod:`.design`)."""

    def metrics(self) -> dict[str, DesignMetric]:
        from rcm_pin.mechanisms.planar_3rrr.design import METRICS

        return dict(METRICS)


class Planar3RRRSingularity(NumericSingularity):
    """A/B of the loop equations and their maps (no named causes)."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """Normalised A and B of the loop equations (:func:`normalised_ab`)."""
        return ABMatrices(*normalised_ab(geometry(mech), *_pose_and_drives(mech, q)), paper=True)

    def workspace_map(self, mech: Mechanism, mode: int, phi: float, n: int) -> DetMap:
        """Normalised det A and det B over the constant-orientation workspace of one
        working mode."""
        from rcm_pin.mechanisms.planar_3rrr import workspace as ws

        grid = ws.Grid.around(geometry(mech), n)
        da, db = ws.det_maps(geometry(mech), grid, float(phi), mode)
        return DetMap(grid.x, grid.y, da, db, MODES[mode], float(phi))


class Planar3RRRFamily(Family):
    """Hooks of the planar 3-RRR (module docstring)."""

    name = "planar_3rrr"
    description = "planar 3-RRR parallel mechanisms (paper 004)"
    closed = True
    capabilities = (
        Planar3RRRPosition(),
        Planar3RRRScenarios(),
        Planar3RRRWorkspace(),
        Planar3RRRMetrics(),
        Planar3RRRSingularity(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: the platform centred at the origin, φ = 0, working mode ``+++``."""
        from rcm_pin.analysis.position import inverse

        return {"home": inverse(mech, np.zeros(3)).solutions[0].q}


FAMILY = Planar3RRRFamily()

__all__ = ["FAMILY", "MODES", "Planar3RRRFamily", "geometry", "normalised_ab"]

# Each module of the family is an attribute of the package, imported on first access
# (``from rcm_pin.mechanisms import <family>`` is the public entry, docs/api.md).
__getattr__, __dir__ = lazy_modules(__name__, ("closed_form", "design", "plots", "workspace"))
