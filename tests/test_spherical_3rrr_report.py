"""The spherical 3-RRR report section's pieces (the whole section runs in ``rcm-pin
reproduce --only spherical``, about 35 s, so here only its fast parts).

Routes: the link angles the section reads from Pinocchio's joint axes against the xacro
arguments; the verdict table's three routes against each other; the accuracy table against
the family's accuracy functions.
"""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.mechanisms.spherical_3rrr import accuracy as acc
from rcm_pin.report import spherical as rep


@pytest.fixture(scope="module")
def mech():
    return rcm_pin.load("spherical_3rrr")


@pytest.mark.parametrize("t1, t2", [(90.0, 90.0), (80.0, 70.0)])
def test_link_angles_from_pinocchio_axes_are_the_xacro_arguments(t1, t2):
    args = {f"theta_{i}{k}": str(t) for i in (1, 2, 3) for k, t in ((1, t1), (2, t2))}
    m = rcm_pin.load("spherical_3rrr", **args)
    angles = rep._axis_angles(m, m.home)
    np.testing.assert_allclose(angles, [t1] * 3 + [t2] * 3, atol=1e-9)  # arccos near 90°: 1e-9


def test_verdict_table_three_routes_agree(mech):
    rows = rep._verdicts(mech, np.random.default_rng(5), n=20)
    assert rows[0] == ("random", 20, 0, 0, 0)
    assert rows[1] == ("type-1 curves", 30, 30, 30, 0)
    # where the curves meet B ≡ 0: type 1 by every route, not type 2 (section text)
    assert rows[2] == ("curve meeting points", 4, 4, 0, 0)


def test_accuracy_table_lines_match_the_family(mech):
    rows, lines = rep._accuracy(mech)
    assert len(lines) == 2 + len(acc.PARAMETERS) and [r["joint"] for r in rows] == list(
        acc.PARAMETERS
    )
    for r, line in zip(rows, lines[2:], strict=True):
        assert line.startswith(f"| {r['joint']} |") and f"{r['relative_difference']:.2%}" in line
        assert r["relative_difference"] < 0.01
