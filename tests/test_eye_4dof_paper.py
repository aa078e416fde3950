"""Paper 002's design chains and the report's table (issue 15 point 2).

Routes: rcm_pin.mechanisms.eye_4dof.design against the paper's equations written out here
(the printed forms with exact coefficients), the slot sweep against the corners of (9) and
(10), and the report section's rows (every differing published number has a reason).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import EXACT

from rcm_pin.linkage.fourbar import FourBar, performance
from rcm_pin.mechanisms.eye_4dof import design as dz
from rcm_pin.report import eye_linkage
from rcm_pin.studies import eye_paper

D = dz.PAPER
MM = 1e3


def test_the_root_solves_the_corrected_equations_3_and_6():
    """(3), (6) with 2 l2 = 150 mm, 2 l3 sin φ, 2 l3 sin γ and the constant −3125 mm²."""
    e = dz.pitch_equations(D)
    l0, l1 = e.frame * MM, e.crank * MM
    c_up, c_down = 100 * math.sin(D.up), 100 * math.sin(D.down)
    eq3 = l0**2 - l1**2 + 150 * l1 - c_up * l0 - 3125
    eq6 = l0**2 - l1**2 - 150 * l1 + c_down * l0 - 3125
    np.testing.assert_allclose([eq3, eq6], [0.0, 0.0], rtol=0, atol=EXACT * l0**2)
    assert e.constant * MM**2 == pytest.approx(-3125.0, abs=1e-9)
    # the printed constant −3024 mm² is not l3² − l2² for any of the printed lengths
    assert abs(50**2 - 75**2 + 3024) == 101


def test_printed_equation_8_and_its_root():
    root = dz.positive_root(0.89, 7.24, -3024.0)
    assert abs(0.89 * root**2 + 7.24 * root - 3024.0) < EXACT * 3024
    assert root == pytest.approx(54.3646, abs=5e-5)


def test_built_linkage_swing_matches_an_independent_dead_centre_construction():
    """ψ at |O1 B| = l2 ∓ l1 by the law of cosines at O2 (no call into rcm_pin.linkage)."""
    g = FourBar(D.frame_built, D.crank_built, D.coupler, D.rocker)
    p = performance(g)
    angles = []
    for r in (g.l2 - g.l1, g.l2 + g.l1):  # angle at O2 between O2→O1 and O2→B
        angles.append(math.acos((g.l0**2 + g.l3**2 - r * r) / (2 * g.l0 * g.l3)))
    up, down = math.pi / 2 - angles[0], angles[1] - math.pi / 2
    np.testing.assert_allclose([p.up, p.down], [up, down], rtol=0, atol=EXACT)


def test_slot_sweep_equals_the_corners_and_the_corrected_formula():
    dp, md = dz.slot_parts(D)
    lo, hi, sweep = dz.slot_sweep(D, n=181)
    np.testing.assert_allclose([hi, -lo, sweep], [dp, md, dp + md], rtol=0, atol=EXACT)
    t = 3 * D.l10 - D.offset + math.sqrt(3.0) * D.l44  # φ + γ = 60°: l4 cancels
    np.testing.assert_allclose(dp + md, t, rtol=0, atol=EXACT)
    # the printed formula (0.36 l4) is DP_min + MD* with DP_min = l00 + l10 − l4 cos 50°
    dp_min = D.offset + D.l10 - D.l4 * math.cos(D.yaw_built)
    printed_exact = dz.slot_formula(D, 1 - math.cos(D.yaw_built), math.sqrt(3.0))
    np.testing.assert_allclose(dp_min + md, printed_exact, rtol=0, atol=EXACT)


def test_implied_l00_reproduces_the_printed_slot_and_the_support_rule():
    assert dz.slot_formula(D, 0.36, 1.73) == pytest.approx(D.slot_printed, abs=EXACT)
    assert D.offset > 2 * D.l10  # the paper's l00 > 2 l10
    d = dz.EyeDesign(l00=0.06)
    assert d.offset == 0.06


def test_yaw_crank_support_spacing_and_lid_drive():
    assert D.l10 == pytest.approx(0.035 * math.sin(math.radians(50)), abs=EXACT)
    cl = 2 * D.l10 + 2 * 0.010 + 0.020 * math.tan(math.radians(50))
    assert dz.support_spacing(D) == pytest.approx(cl, abs=EXACT)
    lid = dz.lid_drive(D)
    assert lid.omega_lid == pytest.approx(0.015 / 0.065, rel=EXACT)
    assert lid.d2 == pytest.approx(0.06439, abs=EXACT)
    # the paper's rewritten clearance form d1 (1 + d2 / (2 d1)) = d1 (1 + u12 / 2)
    assert lid.clearance_bound == pytest.approx(D.d1 * (1 + D.u12 / 2), abs=EXACT)
    assert lid.motor_rpm == pytest.approx(lid.omega_motor * 60 / (2 * math.pi), rel=EXACT)


def test_every_differing_published_number_has_a_reason():
    rows = eye_paper.pitch_rows() + eye_paper.yaw_rows() + eye_paper.lid_rows()
    assert len(rows) >= 30
    for r in rows:
        assert r.agrees or r.reason, r.quantity
        assert math.isfinite(r.computed)
    named = {r.quantity: r for r in rows}
    assert not named["constant l3² − l2² in (3), (6), (8)"].agrees
    assert named["yaw crank l10 = l4 sin α (α = 50°)"].agrees


def test_report_section_runs(tmp_path, monkeypatch):
    monkeypatch.setattr(eye_linkage, "N_RANDOM", 3)
    s = eye_linkage.section(tmp_path)
    assert s.title.startswith("Paper 002")
    assert s.figures == ("eye_pitch_fourbar.png", "eye_clearance_map.png")
    assert (tmp_path / "eye_pitch_fourbar.png").stat().st_size > 0
    assert "| root, O1 on the up side | 55.1745 | 18.3215 | crank-rocker |" in s.body
