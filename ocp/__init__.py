"""CasADi layer of rcm-pin: the symbolic twin of a ``pin.Model`` (mimic joints included),
inverse-kinematics NLPs and trajectory-tracking OCPs built from it."""

from ocp.symbolic import SymbolicModel

__all__ = ["SymbolicModel"]
