"""The position section of the report and the mobility count."""

from __future__ import annotations

import dataclasses

import pytest

import rcm_pin
from rcm_pin.analysis.mobility import somov_malyshev
from rcm_pin.errors import InvalidInputError
from rcm_pin.report import Comparison, comparison_table
from rcm_pin.report.position import position_example
from rcm_pin.report.writer import write_report


def test_position_example_agrees_to_printed_precision():
    rows, distance, residual = position_example()
    assert all(r.agrees for r in rows)
    assert residual < 5e-5 and distance < 1e-4


def test_mobility_of_shipped_mechanisms():
    assert rcm_pin.mobility(rcm_pin.load("rcm_bevel")).W == 6
    assert rcm_pin.mobility(rcm_pin.load("rcm_bevel_4dof")).W == 4
    assert rcm_pin.mobility(rcm_pin.load("rcm_belt")).W == 6


EXPECTED_MOBILITY = {  # name: (Somov–Malyshev W, Chebyshev W, degrees of freedom)
    "rcm_bevel": (6, None, 6),
    "rcm_bevel_4dof": (4, None, 4),
    "rcm_belt": (6, None, 6),
    "rcm_two_mass": (3, None, 3),
    "planar_3rrr": (1, 3, 3),  # planar loops counted in space: 2 redundant rows
    "five_bar": (1, 2, 2),
    "four_bar": (0, 1, 1),
    "panda": (8, None, 8),  # 7 arm joints + one finger (the other mimics it)
    "ur5": (6, None, 6),
}


@pytest.mark.parametrize("name", sorted(EXPECTED_MOBILITY))
def test_mobility_formulas_and_rank_of_every_entry(name):
    mech = rcm_pin.load(name)
    mob = rcm_pin.mobility(mech)
    w, cheb, dof = EXPECTED_MOBILITY[name]
    assert (mob.W, mob.chebyshev, mob.rank_mobility) == (w, cheb, dof)
    assert dof == (mech.loops.dof if mech.loops is not None else mech.nv)
    assert mob.redundant == dof - w


def test_mobility_names_an_uncountable_joint_type():
    mech = rcm_pin.load("rcm_two_mass")
    bad = dataclasses.replace(mech, urdf=mech.urdf.replace('type="prismatic"', 'type="screw"', 1))
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.mobility(bad)
    assert str(err.value) == (
        "joint 'pair24' has type 'screw'; valid: continuous, fixed, floating, planar, "
        "prismatic, revolute"
    )


def test_somov_malyshev_paper_numbers():
    assert somov_malyshev(9, {5: 8, 4: 1, 1: 4}) == 6
    assert somov_malyshev(7, {5: 6, 4: 1, 1: 4}) == 4
    assert somov_malyshev(9, {5: 8, 4: 2, 1: 4}) == 2  # the printed P4 = 2


def test_comparison_table_marks_differences():
    table = comparison_table(
        [Comparison("a", 1.0, 1.0, "m", tolerance=0.0), Comparison("b", 1.0, 2.0, "m", "typo")]
    )
    assert "| a [m] | 1 | 1 | 0 | agrees |" in table
    assert "| b [m] | 1 | 2 | 1 | **differs** | typo |" in table


def test_write_report_position_only(tmp_path):
    path = write_report(tmp_path, only=["position"], quiet=True)
    text = path.read_text()
    assert "Paper 000: position problem and mobility" in text and "W = 6" in text
