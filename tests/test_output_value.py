"""``Output.value`` (one flattened copy of the placement) gives the bits of the former
reading (rotation and translation as nested lists) for every token."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from hypothesis import given, settings
from hypothesis import strategies as st

from rcm_pin.model.output import Output
from rcm_pin.rotations import random_rotations

ROW = {"x": 0, "y": 1, "z": 2}
ANGLE = {"rx": (2, 1), "ry": (0, 2), "rz": (1, 0)}


def former_value(output, oMf):
    out = []
    R, p = oMf.rotation.tolist(), oMf.translation.tolist()
    for c in output.coords:
        if c in ROW:
            out.append(p[ROW[c]])
        elif c == "rotation":
            out += R[0] + R[1] + R[2]
        else:
            i, j = ANGLE[c]
            out.append(math.atan2(R[i][j], R[j][j]))
    return np.array(out)


OUTPUTS = [("x", "y", "z", "rotation"), ("x", "y", "rz"), ("rx",), ("ry", "z"), ("rotation",),
           ("z", "x"), ("rz", "ry", "rx", "y")]  # fmt: skip
PLACEMENTS = [
    pin.SE3(R, t)
    for R, t in zip(
        random_rotations(np.random.default_rng(3), 64),
        np.random.default_rng(4).uniform(-2.0, 2.0, (64, 3)),
        strict=True,
    )
]


@settings(max_examples=100, deadline=None, derandomize=True)
@given(coords=st.sampled_from(OUTPUTS), k=st.integers(0, len(PLACEMENTS) - 1))
def test_value_is_the_former_reading_bit_for_bit(coords, k):
    output = Output("tool", coords)
    M = PLACEMENTS[k]
    np.testing.assert_array_equal(output.value(M), former_value(output, M))


def test_planar_angles_of_elementary_rotations():
    for token, axis in (("rx", 0), ("ry", 1), ("rz", 2)):
        for angle in (-3.0, -0.4, 0.0, 1.2, 3.1):
            w = np.zeros(3)
            w[axis] = angle
            value = Output("f", (token,)).value(pin.SE3(pin.exp3(w), np.zeros(3)))
            assert abs(value[0] - angle) < 1e-12, (token, angle)
