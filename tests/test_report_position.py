"""The position section of the report and the mobility count."""

from __future__ import annotations

import rcm_pin
from rcm_pin.mobility import somov_malyshev
from rcm_pin.report import Comparison, comparison_table, write_report
from rcm_pin.report.position import position_example


def test_position_example_agrees_to_printed_precision():
    rows, distance, residual = position_example()
    assert all(r.agrees for r in rows)
    assert residual < 5e-5 and distance < 1e-4


def test_mobility_of_shipped_mechanisms():
    assert rcm_pin.mobility(rcm_pin.load("rcm_bevel")).W == 6
    assert rcm_pin.mobility(rcm_pin.load("rcm_bevel_4dof")).W == 4
    assert rcm_pin.mobility(rcm_pin.load("rcm_belt")).W == 6


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
