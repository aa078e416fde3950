"""The translational 3-PPaPa parallel mechanism of paper 004 (Fig. 4): the family.

Two models of the same geometry (``xacro/translational_3ppapa.urdf.xacro``): the crank +
mimic parallelograms (``translational_3ppapa``) and the 4R-loop parallelograms
(``translational_3ppapa_loops``, over-constrained). The paper's equations are in
:mod:`.closed_form`, the linear accuracy theory in :mod:`.accuracy`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.accuracy import AccuracyModel, AccuracyReport, AccuracyRow
from rcm_pin.analysis.capabilities import Assemblies, Branches, DefaultPoses, NumericPosition
from rcm_pin.analysis.singularity_model import ABMatrices, NumericSingularity
from rcm_pin.analysis.workspace import WorkspaceModel
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.lazy import lazy_modules
from rcm_pin.mechanisms.translational_3ppapa import accuracy
from rcm_pin.mechanisms.translational_3ppapa.closed_form import (
    LEG_SIGNS,
    MODES,
    SIGN_PATTERNS,
    Geometry3PPaPa,
    a_from_angles,
    a_matrix,
    direct_position,
    inverse_position,
    label,
    leg_angles,
    local,
    platform_point,
    residual,
)
from rcm_pin.mechanisms.translational_3ppapa.direct import DirectSolutions, direct_all, direct_batch
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: The paper's control-reference amplitudes (x, y, z) [m]: the ``regular`` configuration.
REGULAR = (0.1, 0.12, 0.15)


def geometry(mech: Mechanism) -> Geometry3PPaPa:
    """The closed-form geometry of a loaded 3-PPaPa (from its sidecar parameters)."""
    return Geometry3PPaPa.from_params(mech.require_loops().params)


def drive_limits(mech: Mechanism) -> tuple[float, float]:
    """The common drive stroke (lower, upper) [m] of P1, P2, P3 (the URDF limits)."""
    idx = [mech.joint_names.index(f"P{i}") for i in (1, 2, 3)]
    return float(np.max(mech.lower[idx])), float(np.min(mech.upper[idx]))


def diagonal_singularity(g: Geometry3PPaPa) -> float:
    """t* [m] of the type-2 point x = y = z = t* in mode ``++/++/++``: the eigenvalue of the
    circulant A along (1, 1, 1), −1 + t/√(l2² − t²) + t/√(l1² − t²), vanishes (bisection on
    an increasing function of t ∈ (0, min(l1, l2)))."""
    lo, hi = 0.0, min(g.l1, g.l2)
    for _ in range(200):
        t = 0.5 * (lo + hi)
        f = t / np.sqrt(g.l2**2 - t * t) + t / np.sqrt(g.l1**2 - t * t) - 1.0
        lo, hi = (t, hi) if f < 0.0 else (lo, t)
        if hi - lo < 1e-16:
            break
    return 0.5 * (lo + hi)


def joint_values(q: np.ndarray, angles: np.ndarray) -> dict[str, float]:
    """Every tree joint [m, rad]: drives P<i>, cranks c<i><k>, couplers k<i><k> = −crank,
    second cranks d<i><k> = crank (the parallelogram branch)."""
    out: dict[str, float] = {}
    for i in range(3):
        out[f"P{i + 1}"] = float(q[i])
        for k in range(2):
            t = float(angles[i, k])
            out[f"c{i + 1}{k + 1}"], out[f"k{i + 1}{k + 1}"], out[f"d{i + 1}{k + 1}"] = t, -t, t
    return out


def mech_q(mech: Mechanism, q: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Mechanism coordinates of drives q and crank angles (3, 2) (either model)."""
    values = joint_values(q, angles)
    return np.array([values[n] for n in mech.joint_names])


def crank_angles(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """(3, 2) crank angles θ_i, φ_i read from Mechanism coordinates q."""
    names = list(mech.joint_names)
    return np.array([[q[names.index(f"c{i}{k}")] for k in (1, 2)] for i in (1, 2, 3)])


class Translational3PPaPaPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Every working mode reaching P (the paper's explicit solution)."""
        if output.coords != ("x", "y", "z"):
            return super().inverse(mech, target, output)
        g, p = geometry(mech), np.asarray(target, dtype=float)
        sols = inverse_position(g, p)
        if not sols:
            r = min(g.l1, g.l2)
            raise UnreachablePoseError(
                f"{mech.name}: platform point {p.tolist()} m is out of reach (a crank "
                f"cannot span it); valid: |x|, |y|, |z| <= min(l1, l2) = {r:.6g} m"
            )
        return Branches.of(mech, [Branch(mech_q(mech, q, ang), lab) for lab, q, ang in sols])

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """Every assembly mode of the batched direct solver (:mod:`.direct`, ``++/++/++``
        first), as seeds that the generic code polishes on Pinocchio's closures."""
        g = geometry(mech)
        out = []
        for lab, p in direct_all(g, np.asarray(drives, dtype=float)):
            pattern = SIGN_PATTERNS[MODES.index(lab)]
            legs = [leg_angles(g, p, i, pattern[i]) for i in range(3)]
            ang = np.array([x[1:] for x in legs if x is not None])
            out.append(mech_q(mech, np.asarray(drives, dtype=float), ang))
        return Assemblies.of(out)

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """The 64 sign patterns ``s11s12/s21s22/s31s32``."""
        return MODES


class Translational3PPaPaPoses(DefaultPoses):
    """Accuracy at the paper's ``regular`` pose."""

    def accuracy(self, mech: Mechanism) -> np.ndarray:
        return mech.configurations["regular"]


class Translational3PPaPaWorkspace(WorkspaceModel):
    """Reach and det-A-sign volumes per working mode (:mod:`.workspace`), Monte Carlo with
    standard errors beside a grid (option ``grid``); sections through t*."""

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        from rcm_pin.mechanisms.translational_3ppapa import workspace as ws

        samples = 200_000 if samples is None else samples
        if not 1 <= samples <= ws.MAX_SAMPLES:
            raise InvalidInputError(
                f"{samples} workspace samples, each solved in all 64 working modes; valid: "
                f"1..{ws.MAX_SAMPLES} (about 15 s of work at the most)"
            )
        return ws.volumes(
            geometry(mech),
            drive_limits(mech),
            samples,
            int(options.get("grid", 22)),
            seed,
        )

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """Sections x, y, z = 0 and = t* (diagonal type-2 point) with the singular sets."""
        from rcm_pin.mechanisms.translational_3ppapa.plots import sections_figure

        g = geometry(mech)
        mode = str(options.get("mode", MODES[0]))
        return sections_figure(g, Path(path), diagonal_singularity(g), mode)


class Translational3PPaPaSingularity(NumericSingularity):
    """A (paper) and B = I (no named causes, the numeric map)."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """A = ∂F/∂p from the crank angles and B = I (both dimensionless)."""
        return ABMatrices(a_from_angles(crank_angles(mech, q)), np.eye(3), paper=True)


class Translational3PPaPaAccuracy(AccuracyModel):
    """Paper 004's linear theory beside the nonlinear re-solve (:mod:`.accuracy`)."""

    def parameters(self, mech: Mechanism) -> tuple[str, ...]:
        """The link lengths l1, l2, l3 (xacro ``side_1``, ``side_2``, ``offset``)."""
        return ("side_1", "side_2", "offset")

    def report(self, mech: Mechanism, q: np.ndarray) -> AccuracyReport:
        """1 mm errors in l1, l2, l3, drives locked: the linear theory (Cramer's rule,
        denominator det A restored) beside the nonlinear re-solve (:mod:`.accuracy`)."""
        g, qc = geometry(mech), mech.check_q(q)
        drives = qc[list(mech.require_loops().drive_q)]
        angles = crank_angles(mech, qc)
        signs = np.where(np.cos(angles) >= 0.0, 1.0, -1.0)
        p = platform_point(g, drives, angles)
        table = {"mechanism": mech.name, "q": qc, **accuracy.report(g, drives, p, signs, angles)}
        return AccuracyReport.of(table, AccuracyRow.of_output)


class Translational3PPaPaFamily(Family):
    """Hooks of the 3-PPaPa: 64 working modes, assembly modes, A (paper) and B = I."""

    name = "translational_3ppapa"
    description = "translational 3-PPaPa parallel mechanism (paper 004 Fig. 4)"
    closed = True
    capabilities = (
        Translational3PPaPaPosition(),
        Translational3PPaPaPoses(),
        Translational3PPaPaWorkspace(),
        Translational3PPaPaSingularity(),
        Translational3PPaPaAccuracy(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: P = 0, every crank along its drive axis; ``regular``: P at the paper's
        reference amplitudes :data:`REGULAR` (both in mode ``++/++/++``)."""
        _, q, ang = inverse_position(geometry(mech), np.zeros(3))[0]
        _, qr, angr = inverse_position(geometry(mech), np.array(REGULAR))[0]
        return {"home": mech_q(mech, q, ang), "regular": mech_q(mech, qr, angr)}


FAMILY = Translational3PPaPaFamily()
#: Catalogue names of the two parallelogram models (crank + mimic, 4R loops).
MODELS = (FAMILY.name, f"{FAMILY.name}_loops")

__all__ = [
    "FAMILY",
    "LEG_SIGNS",
    "MODELS",
    "MODES",
    "REGULAR",
    "SIGN_PATTERNS",
    "DirectSolutions",
    "Geometry3PPaPa",
    "Translational3PPaPaFamily",
    "a_from_angles",
    "a_matrix",
    "crank_angles",
    "diagonal_singularity",
    "direct_all",
    "direct_batch",
    "direct_position",
    "drive_limits",
    "geometry",
    "inverse_position",
    "joint_values",
    "label",
    "leg_angles",
    "local",
    "mech_q",
    "platform_point",
    "residual",
]

# Each module of the family is an attribute of the package, imported on first access
# (``from rcm_pin.mechanisms import <family>`` is the public entry, docs/api.md).
__getattr__, __dir__ = lazy_modules(
    __name__, ("accuracy", "closed_form", "direct", "plots", "verdicts", "workspace")
)
