"""Four-bar synthesis from the two extreme rocker positions (issue 15 point 1).

Routes: the closed forms of rcm_pin.linkage; the dead-centre equations rebuilt here from
points (law of cosines, no call into the synthesis); the Pinocchio closed loop of the
catalogue's planar four-bar driven through a full crank turn (rcm_pin.studies.four_bar_turn);
the CLI's JSON.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, SOLVER
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.linkage.fourbar import (
    FourBar,
    crank_band_below,
    performance,
    rocker_angle,
    transmission_angle,
    transmission_range,
)
from rcm_pin.linkage.synthesis import LAYOUTS, real_roots, synthesize, valid_or_raise
from rcm_pin.studies.four_bar_turn import crank_turn

UP, DOWN, L2, L3 = math.radians(25.0), math.radians(35.0), 0.075, 0.05  # paper 002


def load(g: FourBar):
    return rcm_pin.load("four_bar", frame=g.l0, crank=g.l1, coupler=g.l2, rocker=g.l3)


def turn(g: FourBar, n: int = 121):
    m = load(g)
    return m, crank_turn(m, m.home, n)


def extremes_from_points(up, down, l2, l3, frame, up_side):
    """|O1 B_u|, |O1 B_d| − the dead-centre lengths [m], with the points built here: O2 at
    the origin, the straight rocker along +y, O1 at distance ``frame`` on the up side
    (x < 0) or the down side (x > 0)."""
    o1 = np.array([-frame if up_side else frame, 0.0])
    b_up, b_down = (
        l3 * np.array([-np.sin(up), np.cos(up)]),
        l3 * np.array([np.sin(down), np.cos(down)]),
    )
    return np.linalg.norm(b_up - o1), np.linalg.norm(b_down - o1)


def check_root(root, up, down, l2, l3):
    """Both extreme-position equations to 1e-12 m: the up extreme is the folded dead
    centre (l2 − l1) with O1 on the up side, the extended one (l2 + l1) on the down side."""
    up_side = root.layout == LAYOUTS[0]
    r_up, r_down = extremes_from_points(up, down, l2, l3, root.frame, up_side)
    s, scale = (-1.0 if up_side else 1.0), max(l2, l3, root.frame)  # relative to the links
    assert abs(r_up - abs(l2 + s * root.crank)) <= EXACT * scale
    assert abs(r_down - abs(l2 - s * root.crank)) <= EXACT * scale
    assert max(abs(root.residual_up), abs(root.residual_down)) <= EXACT * scale**2


def test_paper_target_has_two_crank_rockers_on_both_layouts():
    """Paper 002 found one root (O1 on the up side); the mirrored layout is a second one."""
    roots = synthesize(UP, DOWN, L2, L3)
    assert [r.layout for r in roots] == list(LAYOUTS) and all(r.valid for r in roots)
    for r in roots:
        check_root(r, UP, DOWN, L2, L3)
        p = r.performance
        assert p.grashof_class == "crank-rocker" and r.reason == ""
        np.testing.assert_allclose([p.up, p.down], [UP, DOWN], rtol=0, atol=EXACT)
    # l1 = k l0 with k = l3 (sin φ + sin γ) / (2 l2) (the paper's (7) is k ≈ 0.33)
    k = L3 * (np.sin(UP) + np.sin(DOWN)) / (2 * L2)
    np.testing.assert_allclose([r.crank / r.frame for r in roots], [k, k], rtol=EXACT)


def test_pinocchio_crank_turn_measures_the_target_swing():
    """Each root as the Pinocchio closed loop, driven through a full crank turn."""
    for r in synthesize(UP, DOWN, L2, L3):
        p = r.performance
        m, t = turn(p.linkage)
        lo, hi = (np.pi / 2 - DOWN, np.pi / 2 + UP) if r.layout == LAYOUTS[0] else (
            np.pi / 2 - UP, np.pi / 2 + DOWN)  # fmt: skip
        np.testing.assert_allclose([t.psi_min, t.psi_max], [lo, hi], rtol=0, atol=SOLVER)
        assert len(t.extremes) == 2 and t.max_closure_residual < EXACT
        np.testing.assert_allclose(t.time_ratio, p.time_ratio, rtol=SOLVER)
        np.testing.assert_allclose(t.stroke, p.stroke, rtol=0, atol=SOLVER)
        # extremes at the crank angles of the dead centres
        ext = sorted(t.extremes, key=lambda e: e[1])
        for (theta, _), dc in zip(ext, (p.extended, p.folded), strict=True):
            assert abs(math.remainder(theta - dc.crank, 2 * math.pi)) < SOLVER


def pinocchio_points(m, q):
    pin.framesForwardKinematics(m.model, m.data, q)
    a = m.data.oMi[m.model.getJointId("A")].translation[:2]
    o2 = m.data.oMi[m.model.getJointId("O2")].translation[:2]
    b = m.data.oMf[m.frame_id("rocker_tip")].translation[:2]
    return a, b, o2


def test_closed_forms_equal_pinocchio_over_the_turn():
    """ψ(θ) and μ(θ) on the upper circuit, and the transmission range at θ = 0, π."""
    g = FourBar(0.05419, 0.01788, 0.075, 0.05)
    m, t = turn(g)
    qs = [position_solver(m).direct(m, np.array([th])).seeds[0] for th in t.theta]
    mu = []
    for q in qs:
        a, b, o2 = pinocchio_points(m, q)
        u, v = a - b, o2 - b
        mu.append(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v))
    np.testing.assert_allclose(np.unwrap(rocker_angle(g, t.theta)), t.psi, rtol=0, atol=EXACT)
    np.testing.assert_allclose(transmission_angle(g, t.theta), mu, rtol=0, atol=EXACT)
    np.testing.assert_allclose(transmission_range(g), (min(mu), max(mu)), rtol=0, atol=EXACT)


def test_time_ratio_is_the_classical_crank_offset_formula():
    """Q = (π + β) / (π − β), β the angle at O1 between O1 B_folded and O1 B_extended."""
    for g in (FourBar(0.05419, 0.01788, 0.075, 0.05), FourBar(0.1, 0.02, 0.09, 0.07)):
        p = performance(g)
        r_f, r_e = g.l2 - g.l1, g.l2 + g.l1
        angle = [math.acos((r * r + g.l0**2 - g.l3**2) / (2 * r * g.l0)) for r in (r_f, r_e)]
        beta = abs(angle[0] - angle[1])
        np.testing.assert_allclose(p.time_ratio, (math.pi + beta) / (math.pi - beta), rtol=EXACT)


@pytest.mark.parametrize(
    ("links", "kind"),
    [
        ((0.05419, 0.01788, 0.075, 0.05), "crank-rocker"),
        ((0.05, 0.035, 0.04, 0.03), "non-Grashof triple-rocker"),
        ((0.05, 0.04, 0.045, 0.02), "rocker-crank"),
        ((0.02, 0.04, 0.05, 0.045), "double-crank"),
        ((0.05, 0.04, 0.025, 0.045), "double-rocker"),
        ((0.05, 0.03, 0.05, 0.03), "change-point"),
    ],
)
def test_grashof_classes(links, kind):
    p = performance(FourBar(*links))
    assert p.grashof_class == kind and p.crank_rocker == (kind == "crank-rocker")
    if kind != "crank-rocker":
        assert p.up is None and p.time_ratio is None and p.folded is None


def test_crank_band_of_poor_transmission():
    """μ(θ*) = 40° exactly, μ < 40° inside the band and > 40° outside (sampled)."""
    g, mu = FourBar(0.05419, 0.01788, 0.075, 0.05), math.radians(40.0)
    t = crank_band_below(g, mu)
    assert abs(transmission_angle(g, np.array(t)) - mu) < EXACT
    theta = np.linspace(-np.pi, np.pi, 3601)
    inside = np.abs(theta) < t
    assert np.all(transmission_angle(g, theta[inside]) < mu)
    assert np.all(transmission_angle(g, theta[~inside]) >= mu)
    assert crank_band_below(g, math.radians(10.0)) is None
    assert crank_band_below(g, math.radians(89.0)) == math.pi


def test_real_roots_edge_cases():
    assert real_roots(0.0, 2.0, -4.0) == [2.0]
    assert real_roots(1.0, 0.0, 1.0) == []
    assert real_roots(0.0, 0.0, 1.0) == []
    np.testing.assert_allclose(real_roots(1.0, -1e8, 1.0), [1e-8, 1e8], rtol=1e-15)


def test_no_real_root_and_no_crank_rocker_are_unreachable():
    with pytest.raises(UnreachablePoseError) as e:
        synthesize(UP, DOWN, 0.03, 0.05)
    assert str(e.value) == (
        "no four-bar has its dead centres at up 25 deg and down 35 deg with coupler 0.03 m "
        "and rocker 0.05 m (the quadratic in the frame has no real root, discriminant "
        "-0.00193 m^2 < 0); valid: a longer coupler or a smaller swing"
    )
    roots = synthesize(math.radians(60), math.radians(60), 0.05, 0.05)
    assert roots and not any(r.valid for r in roots)
    with pytest.raises(UnreachablePoseError, match=r"^no crank-rocker swings up 60 deg"):
        valid_or_raise(roots, math.radians(60), math.radians(60))


RANGE = (
    "valid: a length from 1e-06 to 1e+06 m (the equations square the lengths: larger values "
    "overflow double precision)"
)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((math.pi / 2, 0.1, L2, L3), "up = 90 deg; valid: |up| < 90 deg (the rocker tip stays "
         "above the frame line)"),
        ((0.1, -0.2, L2, L3), "up + down = -5.72958 deg; valid: a swing up + down > 0 deg"),
        ((0.1, float("nan"), L2, L3), "down = nan; valid: a finite number"),
        ((0.1, 0.2, 0.0, L3), "coupler = 0 m; " + RANGE),
        ((0.1, 0.2, L2, 1e300), "rocker = 1e+300 m; " + RANGE),
        ((0.1, 0.2, L2, float("inf")), "rocker = inf; valid: a finite number"),
    ],
)  # fmt: skip
def test_bad_synthesis_input(args, message):
    with pytest.raises(InvalidInputError) as e:
        synthesize(*args)
    assert str(e.value) == message


def run(capsys, *argv):
    code = main(list(argv))
    return code, json.loads(capsys.readouterr().out)


KEYS = {"frame", "crank", "grashof", "transmission_angle_deg", "time_ratio", "up_deg", "down_deg"}


def test_cli_synthesize_and_analyse(capsys):
    code, out = run(capsys, "fourbar", "synthesize", "--up", "25", "--down", "35",
                    "--coupler", "0.075", "--rocker", "0.05", "--json")  # fmt: skip
    assert code == 0 and out["count"] == 2 and out["rejected"] == []
    for sol, root in zip(out["solutions"], synthesize(UP, DOWN, L2, L3), strict=True):
        assert set(sol) >= KEYS
        assert sol["frame"] == root.frame and sol["crank"] == root.crank
        np.testing.assert_allclose([sol["up_deg"], sol["down_deg"]], [25, 35], atol=1e-12)
        code, again = run(capsys, "fourbar", "analyse", "--frame", repr(sol["frame"]),
                          "--crank", repr(sol["crank"]), "--coupler", "0.075", "--rocker",
                          "0.05", "--json")  # fmt: skip
        assert code == 0 and set(again) >= KEYS
        if sol["layout"] == LAYOUTS[0]:  # analyse measures up towards O1
            assert {k: again[k] for k in KEYS} == {k: sol[k] for k in KEYS}
        else:
            np.testing.assert_allclose([again["up_deg"], again["down_deg"]], [35, 25], atol=1e-12)


@pytest.mark.parametrize(
    ("argv", "kind", "message"),
    [
        (["synthesize", "--up", "25", "--down", "35", "--coupler", "0.03", "--rocker", "0.05"],
         "UnreachablePoseError", "no four-bar has its dead centres"),
        (["synthesize", "--up", "-25", "--down", "15", "--coupler", "0.075", "--rocker", "0.05"],
         "InvalidInputError", "up + down = -10 deg; valid"),
        (["analyse", "--frame", "0", "--crank", "1", "--coupler", "1", "--rocker", "1"],
         "InvalidInputError", "--frame = 0 m; " + RANGE),
        (["analyse", "--frame", "1e300", "--crank", "1", "--coupler", "1", "--rocker", "1"],
         "InvalidInputError", "--frame = 1e+300 m; " + RANGE),
        (["synthesize", "--up", "20", "--down", "20", "--coupler", "0.3", "--rocker", "1e300"],
         "InvalidInputError", "rocker = 1e+300 m; " + RANGE),
        (["synthesize", "--up", "20", "--down", "20", "--coupler", "1e300", "--rocker", "0.3"],
         "InvalidInputError", "coupler = 1e+300 m; " + RANGE),
        (["synthesize", "--up", "1e300", "--down", "20", "--coupler", "0.3", "--rocker", "0.3"],
         "InvalidInputError", "up = 1e+300 deg; valid: |up| < 90 deg"),
        (["synthesize", "--up", "20", "--down=-inf", "--coupler", "0.3", "--rocker", "0.3"],
         "InvalidInputError", "down = -inf; valid: a finite number"),
        (["analyse", "--frame", "1", "--crank", "0.1", "--coupler", "0.2", "--rocker", "0.3"],
         "InvalidInputError", "links (1.0, 0.1, 0.2, 0.3) [m] cannot be assembled"),
        (["analyse", "--frame", "1"], "UsageError", "rcm-pin fourbar analyse: the following"),
    ],
)  # fmt: skip
def test_cli_bad_input_exits_2(capsys, argv, kind, message):
    code, out = run(capsys, "fourbar", *argv, "--json")
    assert code == 2 and out["error"]["type"] == kind
    assert out["error"]["message"].startswith(message)


def test_cli_analyse_of_a_non_crank_rocker(capsys):
    code, out = run(capsys, "fourbar", "analyse", "--frame", "0.02", "--crank", "0.04",
                    "--coupler", "0.05", "--rocker", "0.045", "--json")  # fmt: skip
    assert code == 0 and out["grashof"] == "double-crank" and out["time_ratio"] is None


angles = st.floats(min_value=-60.0, max_value=80.0)
lengths = st.floats(min_value=0.01, max_value=0.2)


@settings(max_examples=12, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
@given(up=angles, down=angles, l2=lengths, l3=lengths)
def test_random_targets_every_root_exact_and_every_valid_one_simulated(up, down, l2, l3):
    """Random (φ, γ, l2, l3): each real root solves both equations; each crank–rocker root
    swings exactly φ, γ on Pinocchio (the benchmark script counts them over 10^3 draws)."""
    if up + down <= 1.0:
        return
    phi, gam = math.radians(up), math.radians(down)
    try:
        roots = synthesize(phi, gam, l2, l3)
    except UnreachablePoseError:  # second route: the discriminant is negative
        k = l3 * (math.sin(phi) + math.sin(gam)) / (2 * l2)
        assert (l3 * (math.sin(gam) - math.sin(phi))) ** 2 < 4 * (1 - k * k) * (l3**2 - l2**2)
        return
    for r in roots:
        if r.frame > 0:
            check_root(r, phi, gam, l2, l3)
        if r.valid:
            _, t = turn(r.performance.linkage, 61)
            towards, away = t.psi_max - math.pi / 2, math.pi / 2 - t.psi_min  # from O1
            swing = (towards, away) if r.layout == LAYOUTS[0] else (away, towards)
            np.testing.assert_allclose(swing, (phi, gam), rtol=0, atol=SOLVER)
