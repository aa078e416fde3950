"""Where ``ocp`` gets Pinocchio models: the repository's URDFs, the RCM mechanisms through
``rcm_pin.load`` and two reference arms of example-robot-data.

The ``example-robot-data`` 6.0 wheel installs the robot files but no Python module, so
:func:`example_robot_model` reads its URDFs from the installed share directory (offline).
"""

from __future__ import annotations

import importlib.metadata
from pathlib import Path

import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnknownMechanismError

REPO_ROOT = Path(__file__).resolve().parent.parent
URDF_DIR = REPO_ROOT / "urdf"
TEST_DATA_DIR = REPO_ROOT / "tests" / "data"

EXAMPLE_ROBOTS = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
}
#: Tool frame used by the IK examples of each reference arm.
EXAMPLE_TOOL_FRAMES = {"ur5": "tool0", "panda": "panda_hand_tcp"}


def model_from_urdf(path: str | Path, mimic: bool = True) -> pin.Model:
    """Parse a URDF file (mimic joints kept as ``JointModelMimic`` by default)."""
    p = Path(path)
    if not p.is_file():
        raise InvalidInputError(f"no URDF file at {p}")
    return pin.buildModelFromUrdf(str(p), mimic=mimic)


def example_robot_model(name: str, mimic: bool = True) -> pin.Model:
    """``ur5`` or ``panda`` from the installed example-robot-data files."""
    if name not in EXAMPLE_ROBOTS:
        raise UnknownMechanismError(
            f"unknown example robot {name!r}; valid: {', '.join(sorted(EXAMPLE_ROBOTS))}"
        )
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise InvalidInputError("example-robot-data is not installed") from None
    base = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    return model_from_urdf(base / EXAMPLE_ROBOTS[name], mimic=mimic)


def repo_urdfs() -> list[Path]:
    """The rendered URDFs committed in ``urdf/`` (may be empty in a partial checkout)."""
    return sorted(URDF_DIR.glob("*.urdf"))


def mechanism_model(name: str) -> pin.Model:
    """The ``pin.Model`` of a shipped mechanism (``rcm_pin.load(name).model``), falling
    back to ``urdf/<name>.urdf`` when ``rcm_pin.load`` is unavailable."""
    try:
        import rcm_pin

        return rcm_pin.load(name).model
    except ImportError:
        path = URDF_DIR / f"{name}.urdf"
        if not path.is_file():
            raise UnknownMechanismError(f"unknown mechanism {name!r}") from None
        return model_from_urdf(path)


__all__ = [
    "EXAMPLE_ROBOTS",
    "EXAMPLE_TOOL_FRAMES",
    "TEST_DATA_DIR",
    "URDF_DIR",
    "example_robot_model",
    "mechanism_model",
    "model_from_urdf",
    "repo_urdfs",
]
