"""Ordinary serial arms from example-robot-data (Franka Panda, Universal Robots UR5).

Their URDFs come from the installed ``example-robot-data`` distribution (its wheel ships
the robot files under ``cmeel.prefix/share/example-robot-data/robots`` and no Python
module), found through ``importlib.metadata``, never through a repository path. They have
no closed forms here: every analysis takes the numeric routes.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from rcm_pin.errors import InvalidInputError
from rcm_pin.interfaces.viz import Assets
from rcm_pin.model.family import Family
from rcm_pin.model.mechanism import Mechanism

#: URDF of each arm inside the example-robot-data ``robots`` folder.
URDFS = {
    "panda": "panda_description/urdf/panda.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
}
#: SRDF with the arm's reference configurations ("default" becomes ``home``).
SRDFS = {"panda": "panda_description/srdf/panda.srdf"}
#: ``home`` of arms whose SRDF has none: the UR "up" pose, elbow at 90° (regular) [rad].
HOMES = {"ur5": (0.0, -np.pi / 2, np.pi / 2, -np.pi / 2, -np.pi / 2, 0.0)}


def robots_dir() -> Path:
    """The installed example-robot-data ``robots`` folder.

    Raises:
        InvalidInputError: example-robot-data is not installed.
    """
    import importlib.metadata  # ~25 ms to import: only when an arm is loaded

    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise InvalidInputError(
            "example-robot-data is not installed; valid: pip install example-robot-data"
        ) from None
    return Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))


def urdf_path(name: str) -> Callable[[], Path]:
    """A function returning the installed URDF of arm ``name`` (resolved when called)."""

    def path() -> Path:
        return robots_dir() / URDFS[name]

    return path


class ArmAssets(Assets):
    """The meshes of example-robot-data."""

    def mesh_dirs(self, mech: Mechanism) -> tuple[str, ...]:
        """The ``share`` folder that holds the ``example-robot-data`` package."""
        return (str(robots_dir().parent.parent),)


class ArmFamily(Family):
    """Serial arms: numeric routes only; ``home`` from the SRDF or a regular posture."""

    name = "arm"
    description = "ordinary serial arms (example-robot-data)"
    capabilities = (ArmAssets(),)

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: the SRDF's ``default`` state (panda), the UR "up" pose (ur5), else the
        middle of each joint's range; every SRDF state by its own name too."""
        import pinocchio as pin

        out: dict[str, np.ndarray] = {}
        if mech.name in SRDFS:
            model = pin.Model(mech.model)
            pin.loadReferenceConfigurations(model, str(robots_dir() / SRDFS[mech.name]), False)
            for item in model.referenceConfigurations:
                out[item.key()] = mech.from_pin(np.asarray(item.data()))
        if "default" in out:
            out["home"] = out["default"]
        elif mech.name in HOMES:
            out["home"] = np.array(HOMES[mech.name])
        else:
            lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)
            hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
            out["home"] = 0.5 * (lo + hi)
        return out


FAMILY = ArmFamily()

__all__ = ["FAMILY", "URDFS", "ArmFamily", "robots_dir", "urdf_path"]
