"""Output coordinates of a mechanism: what a frame's pose means as the answer of a problem.

An :class:`Output` names a frame and the coordinates of its world pose that the position
problems solve for. Tokens:

* ``x``, ``y``, ``z``: translation components [m];
* ``rx``, ``ry``, ``rz``: the angle [rad] of a rotation about that world axis (a planar
  output; ``rz`` = atan2(R₁₀, R₀₀));
* ``rotation``: the whole orientation R ∈ SO(3) (a spherical or 6-D output).

:data:`NO_OUTPUT` (empty frame, no tokens) stands for a closed mechanism without one.

Values are flat vectors in token order; ``rotation`` takes 9 entries (R row by row).
Velocities, errors and Jacobian rows use the LOCAL_WORLD_ALIGNED frame Jacobian [v; ω] of
the frame: a translation token is one linear row, an angle token one angular row, and
``rotation`` the three angular rows. The error of a value with respect to a target is

    e = [p − p_t ;  wrap(θ − θ_t) ;  log₃(R R_tᵀ)]   (world axes),

so that e → J·δq to first order: Newton on e uses the frame Jacobian rows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.rotations import (
    ROTATION_TOL,
    check_magnitude,
    matrix_to_rpy,
    numeric_array,
    project_to_rotation,
    wrap_angle,
)

TOKENS = ("x", "y", "z", "rx", "ry", "rz", "rotation")
_ROW = {"x": 0, "y": 1, "z": 2, "rx": 3, "ry": 4, "rz": 5}
#: Output of a serial mechanism's tool frame: its whole pose.
POSE = ("x", "y", "z", "rotation")
#: Entries h[4 i + j] = M[i, j] of a flattened 4×4 placement M: the translation tokens,
#: and the angle tokens' atan2(R[i, j], R[j, j]) (rx: R21, R11; ry: R02, R22; rz: R10, R00).
_FLAT = {"x": 3, "y": 7, "z": 11}
_ANGLE = {"rx": (9, 5), "ry": (2, 10), "rz": (4, 0)}


@dataclass(frozen=True)
class Output:
    """Coordinates of one frame's world pose (module docstring).

    Attributes:
        frame: frame name.
        coords: tokens from :data:`TOKENS`, each at most once.
        frame_id: Pinocchio frame id (set when the mechanism is built).
    """

    frame: str
    coords: tuple[str, ...]
    frame_id: int = -1

    def __post_init__(self) -> None:
        if not self.frame and not self.coords:
            return  # NO_OUTPUT: a closed mechanism whose sidecar names no output
        bad = [c for c in self.coords if c not in TOKENS]
        if bad or len(set(self.coords)) != len(self.coords) or not self.coords:
            raise InvalidInputError(
                f"output coordinates {list(self.coords)} are invalid; valid: distinct tokens "
                f"from {', '.join(TOKENS)}"
            )
        angles = {"rx", "ry", "rz"} & set(self.coords)
        if "rotation" in self.coords and angles:
            raise InvalidInputError(
                f"output coordinates {list(self.coords)} mix 'rotation' with planar angles"
            )

    @property
    def present(self) -> bool:
        """Whether there is an output (False for :data:`NO_OUTPUT`)."""
        return bool(self.frame)

    # ------------------------------------------------------------------ layout
    @property
    def rows(self) -> np.ndarray:
        """Rows of the LWA frame Jacobian [v; ω] that the coordinates use."""
        out: list[int] = []
        for c in self.coords:
            out += [3, 4, 5] if c == "rotation" else [_ROW[c]]
        return np.array(out, dtype=int)

    @property
    def dim(self) -> int:
        """Velocity dimension (``rotation`` counts 3)."""
        return len(self.rows)

    @property
    def size(self) -> int:
        """Length of a value vector (``rotation`` counts 9)."""
        return sum(9 if c == "rotation" else 1 for c in self.coords)

    @property
    def angular(self) -> np.ndarray:
        """(dim,) bool: the rows that are angular [rad] (the others are lengths [m])."""
        return self.rows >= 3

    @property
    def velocity_names(self) -> tuple[str, ...]:
        """One name per velocity row (``rotation`` gives ``wx``, ``wy``, ``wz``)."""
        out: list[str] = []
        for c in self.coords:
            out += ["wx", "wy", "wz"] if c == "rotation" else [c]
        return tuple(out)

    def subset(self, coords: tuple[str, ...]) -> Output:
        """The same frame with fewer coordinates (e.g. position only of a pose output).

        Raises:
            InvalidInputError: a token that this output does not have.
        """
        missing = [c for c in coords if c not in self.coords]
        if missing:
            raise InvalidInputError(
                f"output coordinates {missing} are not outputs of frame {self.frame}; "
                f"valid: {', '.join(self.coords)}"
            )
        return Output(self.frame, tuple(coords), self.frame_id)

    # ------------------------------------------------------------------ values
    @cached_property
    def _picks(self) -> tuple[np.ndarray, tuple[tuple[int, int, int], ...]]:
        """Where the value's entries sit in a flattened placement (``h[4 i + j]`` =
        M[i, j]): the entry per value entry (an angle's numerator), and per angle token
        (its position, i, j) for atan2(h[i], h[j])."""
        picks: list[int] = []
        angles: list[tuple[int, int, int]] = []
        for c in self.coords:
            if c == "rotation":
                picks += [0, 1, 2, 4, 5, 6, 8, 9, 10]
            elif c in _FLAT:
                picks.append(_FLAT[c])
            else:
                i, j = _ANGLE[c]
                angles.append((len(picks), i, j))
                picks.append(i)
        return np.array(picks, dtype=np.intp), tuple(angles)

    @property
    def layout(self) -> tuple[tuple[int, ...], tuple[tuple[int, int, int], ...]]:
        """How :meth:`value` reads a placement's homogeneous matrix h flattened row by row:
        value[k] = h[picks[k]], except at each angle (k, i, j): atan2(h[i], h[j])."""
        picks, angles = self._picks
        return tuple(picks.tolist()), angles

    def value(self, oMf: pin.SE3) -> np.ndarray:
        """Value vector (size,) of a frame placement."""
        picks, angles = self._picks
        h = oMf.homogeneous
        out = h.take(picks)  # the entries, copied by one numpy call
        for k, i, j in angles:
            out[k] = math.atan2(h.item(i), h.item(j))  # np.arctan2's value, bit for bit
        return out

    def error(self, value: np.ndarray, target: np.ndarray) -> np.ndarray:
        """e (dim,) of a value with respect to a target (module docstring)."""
        out = []
        k = 0
        for c in self.coords:
            if c == "rotation":
                R, Rt = value[k : k + 9].reshape(3, 3), target[k : k + 9].reshape(3, 3)
                out.append(pin.log3(R @ Rt.T))
                k += 9
            elif c in ("x", "y", "z"):
                out.append(np.array([value[k] - target[k]]))
                k += 1
            else:
                out.append(np.atleast_1d(wrap_angle(value[k] - target[k])))
                k += 1
        return np.concatenate(out)

    def coerce(self, target: Any, name: str = "target") -> np.ndarray:
        """A validated value vector from a flat vector (rotation as 9 numbers or a 3×3).

        A rotation that is orthonormal within :data:`rcm_pin.rotations.ROTATION_TOL` is
        projected onto SO(3).

        Raises:
            InvalidInputError: not numeric, wrong length, non-finite entries or an entry
                beyond :data:`rcm_pin.rotations.MAX_ABS` [m, rad].
            NotARotationError: a rotation too far from SO(3).
        """
        arr = numeric_array(target, name)
        if self.coords == ("rotation",) and arr.shape == (3, 3):
            arr = arr.reshape(9)
        if arr.shape != (self.size,):
            raise InvalidInputError(
                f"{name} has shape {arr.shape}; valid: ({self.size},) values of "
                f"{', '.join(self.coords)} of frame {self.frame}"
            )
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(f"{name} has NaN or infinite entries: {arr.tolist()}")
        check_magnitude(arr, name)
        out = arr.copy()
        k = 0
        for c in self.coords:
            if c == "rotation":
                R, _ = project_to_rotation(arr[k : k + 9].reshape(3, 3), ROTATION_TOL)
                out[k : k + 9] = R.reshape(9)
                k += 9
            else:
                k += 1
        return out

    def to_json(self, value: np.ndarray) -> dict[str, Any]:
        """``{token: value}``; a rotation also as the papers' angles (α, β, γ) [rad]."""
        out: dict[str, Any] = {}
        k = 0
        for c in self.coords:
            if c == "rotation":
                R = value[k : k + 9].reshape(3, 3)
                out["rotation"] = R.tolist()
                out["angles"] = [float(a) for a in matrix_to_rpy(R)]
                k += 9
            else:
                out[c] = float(value[k])
                k += 1
        return out


#: The output of a closed mechanism whose sidecar names none (a LAAS ``robot.yaml``): no
#: coordinates, so values are empty and Jacobians have no rows; commands that need an
#: output refuse it (:func:`rcm_pin.model.output_choice.require_output`).
NO_OUTPUT = Output("", (), 0)

__all__ = ["NO_OUTPUT", "POSE", "TOKENS", "Output"]
