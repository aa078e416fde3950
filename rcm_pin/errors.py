"""Typed errors of rcm-pin.

Every error the toolkit raises on bad input derives from :class:`RcmPinError`, so a
caller can catch one class. Each message says what was wrong and what is valid.
"""

from __future__ import annotations


class RcmPinError(Exception):
    """Base class of every rcm-pin error."""


class UnknownMechanismError(RcmPinError, KeyError):
    """A mechanism name that rcm-pin does not ship."""

    def __str__(self) -> str:  # KeyError quotes its message; keep it readable.
        return str(self.args[0]) if self.args else ""


class UnknownFrameError(RcmPinError, KeyError):
    """A frame or joint name that the model does not have."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class XacroArgumentError(RcmPinError, ValueError):
    """A malformed, unknown or out-of-range xacro argument."""


class InvalidInputError(RcmPinError, ValueError):
    """An input array of the wrong shape or with NaN / infinite entries."""


class NotARotationError(RcmPinError, ValueError):
    """A matrix that is too far from a rotation matrix to be projected onto one."""


class UnreachablePoseError(RcmPinError, ValueError):
    """A pose that no configuration of the mechanism reaches."""


class JointLimitError(RcmPinError, ValueError):
    """A configuration, or every solution for a pose, outside the joint limits."""


class SingularConfigurationError(RcmPinError, ValueError):
    """A singular (degenerate) configuration where a regular one is required."""


class SnapshotError(RcmPinError, RuntimeError):
    """Headless Chromium is missing or failed to write a screenshot."""


class SolverError(RcmPinError, RuntimeError):
    """A numerical solver that failed to converge or reported infeasibility."""


__all__ = [
    "InvalidInputError",
    "JointLimitError",
    "NotARotationError",
    "RcmPinError",
    "SingularConfigurationError",
    "SnapshotError",
    "SolverError",
    "UnknownFrameError",
    "UnknownMechanismError",
    "UnreachablePoseError",
    "XacroArgumentError",
]
