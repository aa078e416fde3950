"""Typed errors of rcm-pin.

Every error the toolkit raises on bad input derives from :class:`RcmPinError`, so a
caller can catch one class. Each message says what was wrong and what is valid.

Optional features come with extras of the ``rcm-pin`` distribution (:data:`EXTRAS`);
:func:`require` imports a package of an extra or raises :class:`MissingExtraError`
with the install command.
"""

from __future__ import annotations

import importlib
import types


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


class UnsupportedJointError(InvalidInputError):
    """A URDF joint a Mechanism has no coordinates for (``floating``, ``planar``)."""


class PackageNotFoundError(RcmPinError, LookupError):
    """A ROS package (``$(find pkg)``, ``package://pkg/...``) found in no searched folder;
    the message names it and ``--package-dir`` / ``package_dirs=``."""


class MeshLocationError(RcmPinError, ValueError):
    """A mesh file outside the description's folders and the declared ones; the message
    names ``--mesh-dir`` / ``mesh_dirs=``, which allow it."""


class UntrustedXacroError(InvalidInputError):
    """An expression of an untrusted xacro file that is not on the allow-list of
    :mod:`rcm_pin.model.xacro_safety` (the file is data, not code).

    Attributes:
        file: the xacro file of the expression.
        line: its line (None: an expression built while rendering).
        expression: the expression text.
    """

    def __init__(
        self, message: str, *, file: str = "", line: int | None = None, expression: str = ""
    ) -> None:
        super().__init__(message)
        self.file, self.line, self.expression = file, line, expression


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


class FolderBusyError(RcmPinError, RuntimeError):
    """An output folder locked by another run (the message names its PID); exit 2."""


class ComputationLostError(SolverError):
    """A computation that could not finish because its workers or its Dask scheduler were
    lost; what had finished is kept. A failed solve to the CLI (exit 3)."""


class CodeMismatchError(RcmPinError, RuntimeError):
    """A worker whose code hash differs from the client's (other sources or package
    versions): its results would not be those of the client's code, so it refuses."""


class SolutionNotFoundError(SolverError):
    """A numeric search (e.g. the multistart inverse kinematics) that found no solution
    within its budget, where nothing proves that none exists (unlike
    :class:`UnreachablePoseError`); more starts may find one."""


class MissingExtraError(RcmPinError, ImportError):
    """An optional package that a feature needs is not installed (an extra of rcm-pin);
    the message names the package, the feature and the ``pip install`` command."""


#: The extras of the ``rcm-pin`` distribution (pyproject.toml) -> the feature they enable.
EXTRAS = {
    "design": "design studies (rcm-pin sweep / optimize)",
    "arms": "the programmable RCM on arms (rcm-pin rcm-track on an arm)",
    "report": "the import-graph section cache of rcm-pin reproduce",
    "mujoco": "loading and checking MuJoCo exports (rcm_pin.export.load_mujoco)",
}
#: Distribution names of the optional modules whose import name differs.
_DISTRIBUTIONS = {"pink": "pin-pink", "distributed": "dask[distributed]"}


def require(extra: str, module: str) -> types.ModuleType:
    """``module`` imported, or a :class:`MissingExtraError` naming the extra to install.

    Args:
        extra: the extra of rcm-pin that provides the module (a key of :data:`EXTRAS`).
        module: the module to import, e.g. ``"pandas"`` or ``"pink.tasks"``.

    Raises:
        MissingExtraError: the module (or a package it needs) cannot be imported, e.g.
            "pandas, needed for design studies (rcm-pin sweep / optimize), is not installed;
            valid: pip install 'rcm-pin[design]'".
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.partition(".")[0]
        package = _DISTRIBUTIONS.get(top, top)
        missing = isinstance(exc, ModuleNotFoundError) and exc.name in (top, module)
        what = "is not installed" if missing else f"cannot be imported ({exc})"
        raise MissingExtraError(
            f"{package}, needed for {EXTRAS[extra]}, {what}; valid: pip install 'rcm-pin[{extra}]'",
            name=module,
        ) from exc


__all__ = [
    "EXTRAS",
    "CodeMismatchError",
    "ComputationLostError",
    "FolderBusyError",
    "InvalidInputError",
    "JointLimitError",
    "MeshLocationError",
    "MissingExtraError",
    "NotARotationError",
    "PackageNotFoundError",
    "RcmPinError",
    "SingularConfigurationError",
    "SnapshotError",
    "SolutionNotFoundError",
    "SolverError",
    "UnknownFrameError",
    "UnknownMechanismError",
    "UnreachablePoseError",
    "UnsupportedJointError",
    "UntrustedXacroError",
    "XacroArgumentError",
    "require",
]
