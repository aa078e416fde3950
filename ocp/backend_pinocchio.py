"""Optional backend: Pinocchio's own CasADi bindings (``pinocchio.casadi``).

The PyPI ``pin`` wheel (used here) is built without them, so :data:`AVAILABLE` is False
and :class:`PinocchioCasadiBackend` raises :class:`~rcm_pin.errors.InvalidInputError`.
With a conda / source build of Pinocchio that has ``pinocchio.casadi``, the same
:class:`~ocp.symbolic.SymbolicModel` interface evaluates Pinocchio's templated
algorithms on ``casadi.SX`` instead of :mod:`ocp.kinematics` / :mod:`ocp.dynamics`.
This path is not exercised by this repository's tests (it cannot be here); the native
backend is the reference and is tested against numeric Pinocchio.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError

try:  # pragma: no cover - depends on the Pinocchio build
    import pinocchio.casadi as cpin  # type: ignore[import-not-found]

    AVAILABLE = True
except ImportError:  # the PyPI wheel
    cpin = None
    AVAILABLE = False


class PinocchioCasadiBackend:  # pragma: no cover - needs pinocchio.casadi
    """Frame placements, Jacobians, RNEA and CRBA from ``pinocchio.casadi``."""

    def __init__(self, model: pin.Model, sym: str) -> None:
        if not AVAILABLE:
            raise InvalidInputError(
                "backend='pinocchio' needs pinocchio.casadi, which the PyPI 'pin' wheel "
                "does not ship; use backend='native' (the default)"
            )
        if sym != "SX":
            raise InvalidInputError("backend='pinocchio' supports sym='SX' only")
        self.cmodel = cpin.Model(model)
        self.cdata = self.cmodel.createData()

    def placement(self, q: Any, fid: int) -> tuple[Any, Any]:
        cpin.framesForwardKinematics(self.cmodel, self.cdata, q)
        oMf = self.cdata.oMf[fid]
        return oMf.translation, oMf.rotation

    def jacobian(self, q: Any, fid: int, reference: str) -> Any:
        frame = getattr(pin.ReferenceFrame, reference)
        return cpin.computeFrameJacobian(self.cmodel, self.cdata, q, fid, frame)

    def rnea(self, q: Any, v: Any, a: Any, gravity: np.ndarray) -> Any:
        if np.any(gravity != np.asarray(self.cmodel.gravity.linear, dtype=float)):
            g = cpin.computeGeneralizedGravity(self.cmodel, self.cdata, q)
            return cpin.rnea(self.cmodel, self.cdata, q, v, a) - g
        return cpin.rnea(self.cmodel, self.cdata, q, v, a)

    def crba(self, q: Any) -> Any:
        m = cpin.crba(self.cmodel, self.cdata, q, pin.Convention.WORLD)
        return ca.triu(m) + ca.triu(m, False).T


__all__ = ["AVAILABLE", "PinocchioCasadiBackend"]
