"""How far nine numbers are from a rotation, in plain arithmetic (one formula, three users).

The fast paths that take a rotation as given (``rcm_pin.analysis.pose_target``, the scalar
IK of the RCM family, its compiled twin ``ocp.kernels.branches_function``) decide with the
same first-order test whether R may skip the SVD projection: ½‖RᵀR − I‖_F (what the
projection would move R by, to first order) and det R > 0. :func:`so3_defect` computes
both parts with ``+``, ``-`` and ``*`` only, in a fixed order, so Python floats and CasADi
symbols give the same bits (the compiled twin is bit-identical to the numpy route).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any


def so3_defect(r: Sequence[Any]) -> tuple[Any, Any]:
    """(‖RᵀR − I‖_F², det R) of R given row by row as 9 entries (floats or CasADi symbols);
    the first-order distance of R from SO(3) is ½√ of the first."""
    x0, y0, z0, x1, y1, z1, x2, y2, z2 = r  # columns x, y, z of R (rows 0..2)
    gxx = x0 * x0 + x1 * x1 + x2 * x2 - 1.0
    gyy = y0 * y0 + y1 * y1 + y2 * y2 - 1.0
    gzz = z0 * z0 + z1 * z1 + z2 * z2 - 1.0
    gxy, gxz = x0 * y0 + x1 * y1 + x2 * y2, x0 * z0 + x1 * z1 + x2 * z2
    gyz = y0 * z0 + y1 * z1 + y2 * z2
    sq = gxx * gxx + gyy * gyy + gzz * gzz + 2.0 * (gxy * gxy + gxz * gxz + gyz * gyz)
    det = z0 * (x1 * y2 - x2 * y1) + z1 * (x2 * y0 - x0 * y2) + z2 * (x0 * y1 - x1 * y0)
    return sq, det


__all__ = ["so3_defect"]
