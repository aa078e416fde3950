"""Hooks of the eye linkage: closed-form direct and inverse positions, ``home``."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.linkage.fourbar import performance
from rcm_pin.mechanisms.eye_4dof.closed_form import (
    EyeGeometry,
    gaze_angles,
    joint_values,
    pitch_cranks,
    yaw_cranks,
)
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Frames read by :func:`outputs`.
OUTPUT_FRAMES = ("eye_1", "eye_2", "lid_arm", "camera_2")
#: Working modes of the inverse: pitch crank side × yaw crank pin ahead (f) / behind (b).
MODES = ("+f", "+b", "-f", "-b")


def geometry(mech: Mechanism) -> EyeGeometry:
    """The closed-form geometry of a loaded eye linkage."""
    return EyeGeometry.from_params(mech.require_loops().params)


def to_q(mech: Mechanism, values: dict[str, float]) -> np.ndarray:
    """Pinocchio configuration from joint values by name."""
    q = np.zeros(mech.nq)
    for name, v in values.items():
        q[mech.model.joints[mech.model.getJointId(name)].idx_q] = v
    return q


def outputs(mech: Mechanism, q: np.ndarray) -> dict[str, float]:
    """The linkage's outputs at a closed configuration, from Pinocchio's frames [rad]: gaze
    elevation and azimuth of each eye (frames ``eye_1``, ``eye_2``), the lid angle (frame
    ``lid_arm`` = Ry(λ)) and the camera roll (frame ``camera_2``)."""
    pin.framesForwardKinematics(mech.model, mech.data, q)
    rot = {f: np.asarray(mech.data.oMf[mech.frame_id(f)].rotation) for f in OUTPUT_FRAMES}
    out = {}
    for i in (1, 2):
        e, a, _ = gaze_angles(rot[f"eye_{i}"])
        out[f"elevation_{i}"], out[f"azimuth_{i}"] = e, a
    out["lid"] = math.atan2(float(rot["lid_arm"][0, 2]), float(rot["lid_arm"][0, 0]))
    out["roll"] = gaze_angles(rot["camera_2"])[2]
    return out


def gaze_range(g: EyeGeometry) -> tuple[tuple[float, float], float]:
    """((e_min, e_max), α_max) [rad]: the pitch rocker's dead centres and asin(l10 / l4)."""
    p = performance(g.pitch)
    if p.rocker_range is None:
        return (-math.pi, math.pi), math.asin(min(1.0, g.l10 / g.l4))
    lo, hi = p.rocker_range
    return (lo - math.pi / 2, hi - math.pi / 2), math.asin(min(1.0, g.l10 / g.l4))


class EyePosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Drives for a camera orientation R = Ry(−e) Rz(α) Rx(ρ) (lid at 0)."""
        if output.coords != ("rotation",):
            return super().inverse(mech, target, output)
        g = geometry(mech)
        e, alpha, roll = gaze_angles(np.asarray(target, dtype=float).reshape(3, 3))
        t1s, t2s = pitch_cranks(g, e), yaw_cranks(g, alpha)
        (lo, hi), amax = gaze_range(g)
        if not t1s or not t2s or not lo - 1e-12 <= e <= hi + 1e-12:
            raise UnreachablePoseError(
                f"{mech.name}: gaze elevation {math.degrees(e):.6g} deg, azimuth "
                f"{math.degrees(alpha):.6g} deg is not reachable; valid: elevation in "
                f"[{math.degrees(lo):.6g}, {math.degrees(hi):.6g}] deg, |azimuth| <= "
                f"{math.degrees(amax):.6g} deg"
            )
        out = []
        for i, t1 in enumerate(t1s):
            for k, t2 in enumerate(t2s):
                values = joint_values(g, np.array([t1, t2, 0.0, roll]))
                if values is not None:
                    out.append(Branch(to_q(mech, values), MODES[2 * i + k]))
        return Branches.of(mech, out)

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """The upper circuit of the pitch four-bar and the principal yaw (|α| < π/2)."""
        values = joint_values(geometry(mech), np.asarray(drives, dtype=float))
        return Assemblies.of([] if values is None else [to_q(mech, values)])

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """Pitch crank side (+/−) × yaw crank pin ahead / behind (f/b)."""
        return MODES


class EyeFamily(Family):
    """The eye linkage: every sub-linkage in closed form (:mod:`.closed_form`)."""

    name = "eye_4dof"
    description = "spatial four-DOF eye linkage (paper 002)"
    closed = True
    capabilities = (EyePosition(),)

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: every drive at 0; ``straight``: gaze straight ahead (mode ``+f``)."""
        g = geometry(mech)
        home = joint_values(g, np.zeros(4))
        out = {} if home is None else {"home": to_q(mech, home)}
        cranks = pitch_cranks(g, 0.0)
        if cranks:
            straight = joint_values(g, np.array([cranks[0], 0.0, 0.0, 0.0]))
            if straight is not None:
                out["straight"] = to_q(mech, straight)
        return out


FAMILY = EyeFamily()

__all__ = [
    "FAMILY",
    "MODES",
    "OUTPUT_FRAMES",
    "EyeFamily",
    "gaze_range",
    "geometry",
    "outputs",
    "to_q",
]
