"""A pose target of the inverse problem read without the general route's array passes.

:func:`rcm_pin.inverse` reads a target by the general route (``_as_value`` then
:meth:`rcm_pin.model.output.Output.coerce`: numeric conversion, shape, finiteness and
magnitude checks, the last row of a 4×4, the SVD projection of the rotation onto SO(3)),
about a dozen numpy calls for one pose. :func:`plain_pose` reads the common case, a
float64 4×4 / 3×4 matrix of a pose output (x, y, z, rotation), in scalar arithmetic and
returns None for anything else, which then takes the general route with its checks and
its typed errors. It accepts only what the general route accepts (last row within
:data:`~rcm_pin.rotations.LAST_ROW_TOL`, every entry finite within
:data:`~rcm_pin.rotations.MAX_ABS`, det R > 0) and keeps R as given only when the SVD
projection would move it by less than :data:`KEEP_TOL`; so the value differs from the
general route's by less than that (tests/test_branch_check.py compares both).
"""

from __future__ import annotations

import math
from operator import itemgetter
from typing import Any

import numpy as np

from rcm_pin.model.output import POSE, Output
from rcm_pin.model.so3_defect import so3_defect
from rcm_pin.rotations import LAST_ROW_TOL, MAX_ABS

#: R is kept as given when its distance from SO(3) (first order: ½‖RᵀR − I‖_F, what the
#: SVD projection would move it by) is at most this: rotations computed by forward
#: kinematics (~1e-16) pass; the results then differ from the projected route's by
#: less than 1e-14, a hundredth of the 1e-12 they are compared at.
KEEP_TOL = 1e-14


#: R row by row from the entries of a 3×4 / 4×4 matrix (row-major).
_ROTATION = itemgetter(0, 1, 2, 4, 5, 6, 8, 9, 10)
#: The value vector (x, y, z, R row by row) from the same entries.
_VALUE = np.array([3, 7, 11, 0, 1, 2, 4, 5, 6, 8, 9, 10])


def plain_pose(output: Output, target: Any, screen: bool = True) -> np.ndarray | None:
    """The value vector (x, y, z, R row by row) of a plain pose matrix, or None when the
    target needs the general route (module docstring). ``screen=False`` skips the test of
    R (distance from SO(3) ≤ KEEP_TOL, det R > 0) for a caller that makes it itself: the
    ``serial_branches`` kernel declines such an R (the same arithmetic, the same bits)."""
    if (
        output.coords != POSE
        or type(target) is not np.ndarray
        or target.dtype != np.float64
        or target.shape not in ((4, 4), (3, 4))
    ):
        return None
    flat = target.ravel()
    c = flat.tolist()
    if len(c) == 16 and not (
        abs(c[12]) <= LAST_ROW_TOL
        and abs(c[13]) <= LAST_ROW_TOL
        and abs(c[14]) <= LAST_ROW_TOL
        and abs(c[15] - 1.0) <= LAST_ROW_TOL
    ):
        return None
    if not math.hypot(*c) <= MAX_ABS:  # NaN and inf fail too
        return None
    if screen:
        sq, det = so3_defect(_ROTATION(c))
        if not (0.5 * math.sqrt(sq) <= KEEP_TOL and det > 0.0):
            return None
    return flat[_VALUE]  # a new array (fancy indexing copies): the same bits as c


__all__ = ["KEEP_TOL", "plain_pose"]
