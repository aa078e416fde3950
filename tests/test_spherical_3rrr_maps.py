"""Spherical 3-RRR singularity maps (tilt-and-torsion angles), singular curves and the cone.

Routes: the batched measures of :mod:`maps` against the per-pose closed form
(:func:`closed_form.measures` on :func:`closed_form.inverse_position`); the singular curves
against the geometry (v_i = ±u_i) and Pinocchio's A/B verdicts; the cone of the curve route
against the grid + SLSQP route, which never builds a curve.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXACT, SOLVER

import rcm_pin
from rcm_pin.analysis.loop_velocity import classify
from rcm_pin.mechanisms import spherical_3rrr as s3
from rcm_pin.mechanisms.spherical_3rrr import closed_form as sc
from rcm_pin.mechanisms.spherical_3rrr import maps, plots, workspace
from rcm_pin.rotations import random_rotations
from rcm_pin.rotations import wrap_angle as wrap


@pytest.fixture(scope="module")
def mech():
    return rcm_pin.load("spherical_3rrr")


@pytest.fixture(scope="module")
def g(mech):
    return s3.geometry(mech)


def test_tilt_torsion_angles_round_trip_and_mean_what_they_say(g):
    n = maps.symmetry_axis(g)
    np.testing.assert_allclose(n, np.ones(3) / np.sqrt(3), atol=EXACT)
    R = random_rotations(np.random.default_rng(1), 200)
    tilt, az, tor = maps.tt_angles(n, R)
    np.testing.assert_allclose(maps.tt_rotation(n, tilt, az, tor), R, atol=EXACT)
    # tilt is the angle between the platform axis R n and n (second route: arccos of n·Rn)
    np.testing.assert_allclose(tilt, np.arccos(np.clip(R @ n @ n, -1, 1)), atol=1e-7)
    # a pure torsion turns about n: R n = n
    Rt = maps.tt_rotation(n, 0.0, 0.3, 0.7)
    np.testing.assert_allclose(Rt @ n, n, atol=EXACT)
    np.testing.assert_allclose(np.trace(Rt), 1 + 2 * np.cos(0.7), atol=EXACT)


def test_batched_measures_match_the_closed_form_in_every_mode(g):
    R = random_rotations(np.random.default_rng(2), 40)
    for mode in range(8):
        t1, t2 = maps.measures(g, R, mode)
        ref = np.array([sc.measures(g, r, sc.inverse_position(g, r)[mode]) for r in R])
        np.testing.assert_allclose(np.c_[t1, t2], ref, atol=EXACT)


def test_leg_roots_batch_the_per_pose_roots_and_close_every_leg():
    """One leg-coefficient route for one orientation and for a batch: the same roots, and
    each mode's drives close every loop (F_i = A cos φ + B sin φ + C = 0)."""
    gg = s3.geometry(rcm_pin.load("spherical_3rrr", theta_12="70", theta_22="75"))
    R = random_rotations(np.random.default_rng(4), 60)
    batch = sc.leg_roots(gg, R)
    a, b, c = sc.leg_coefficients(gg, R)
    reachable = 0
    for k, r in enumerate(R):
        for got, one in zip((x[k] for x in batch), sc.leg_roots(gg, r), strict=True):
            np.testing.assert_allclose(got, one, rtol=0, atol=EXACT)
        if np.all(batch[1][k] >= 0):
            reachable += 1
            for phi in sc.inverse_position(gg, r):
                f = a[k] * np.cos(phi) + b[k] * np.sin(phi) + c[k]
                assert np.max(np.abs(f)) < EXACT
                assert np.max(np.abs(sc.loop_residual(gg, r, phi))) < EXACT
    assert reachable > 10


def test_signed_determinants_match_the_family_a_b():
    m = rcm_pin.load("spherical_3rrr", theta_12="70", theta_22="75", theta_31="80")
    gg = s3.geometry(m)
    rots = random_rotations(np.random.default_rng(6), 30)
    rots = rots[[bool(np.all(sc.leg_roots(gg, r)[1] >= 0)) for r in rots]]
    assert len(rots) > 5
    for mode in (0, 6):
        det_a, det_b = maps.determinants(gg, rots, mode)
        for r, da, db in zip(rots, det_a, det_b, strict=True):
            a_mat, b_mat = s3.normalised_ab(gg, r, sc.inverse_position(gg, r)[mode])
            np.testing.assert_allclose([da, db], [np.linalg.det(a_mat), np.linalg.det(b_mat)],
                                       atol=EXACT)  # fmt: skip


def test_singular_curves_are_v_along_u_and_singular_for_pinocchio(mech, g):
    n = maps.symmetry_axis(g)
    curves = maps.singular_curves(g, n, samples=13)
    assert len(curves) == 6
    for c in curves:
        R = maps.tt_rotation(n, c["tilt"], c["azimuth"], c["torsion"])
        v = R @ g.v0[c["leg"] - 1]
        np.testing.assert_allclose(v @ g.u[c["leg"] - 1], c["sign"], atol=EXACT)
        # one leg aligned: every row of A is ⊥ u_i (v_j, u_j ⊥ u_i for j ≠ i), type 2 too;
        # where all three legs align (the curves meet) the free drives decide det A
        rho = np.linalg.norm(np.cross(g.u, np.einsum("sab,ib->sia", R, g.v0)), axis=2)
        single = np.sort(rho, axis=1)[:, 1] > 1e-6
        assert 0 < single.sum() < len(R)
        for mode in range(8):
            t1, t2 = maps.measures(g, R, mode)
            assert np.max(t1) < EXACT and np.max(t2[single]) < EXACT
    # Pinocchio's A and B at a curve point (mode +++): type 1 and type 2
    R = maps.curve_rotations(g, 0, 1.0, np.array([0.4]))[0]
    verdict = classify(mech, s3.full_q(mech, R, sc.inverse_position(g, R)[0]))
    assert verdict.type1 and verdict.type2


def test_the_minus_curves_lie_in_the_torsion_slice_minus_60_degrees(g):
    """Reported in the section: the three curves v_i = −u_i have σ = −60° wherever σ is
    defined (θ < π)."""
    n = maps.symmetry_axis(g)
    for c in maps.singular_curves(g, n, samples=181):
        defined = c["tilt"] < np.pi - 1e-6
        off = np.abs(wrap(c["torsion"][defined] + np.radians(60.0)))
        assert (np.max(off) < 1e-9) == (c["sign"] < 0)


def test_pure_torsion_of_120_degrees_is_singular(g):
    """Rot(n, 120°) permutes the axes x → y → z → x, so v_1 = R e_z = e_x = u_1: the cone
    of any torsion range that reaches 120° is empty."""
    n = maps.symmetry_axis(g)
    R = maps.tt_rotation(n, 0.0, 0.0, 2 * np.pi / 3)
    np.testing.assert_allclose(R @ np.array([1.0, 0, 0]), [0, 1.0, 0], atol=EXACT)
    assert maps.measures(g, R)[0] < EXACT
    assert workspace.cone_from_curves(g, n, np.radians(120.0)) < 1e-9


@pytest.mark.parametrize("sigma_deg", [0.0, 45.0, 100.0])
def test_cone_two_routes_agree(g, sigma_deg):
    n = maps.symmetry_axis(g)
    a = workspace.cone_from_curves(g, n, np.radians(sigma_deg))
    b = workspace.cone_from_grid(g, n, np.radians(sigma_deg), steps=(37, 48, 13))
    assert 0 < a < np.pi
    np.testing.assert_allclose(a, b, atol=SOLVER)
    # inside the cone every sampled orientation of the torsion range is regular
    torsions = np.linspace(-1, 1, 5) * np.radians(sigma_deg)
    grid = np.meshgrid(np.linspace(0, 0.999 * a, 9), np.linspace(-np.pi, np.pi, 16), torsions)
    R = maps.tt_rotation(n, *grid)
    assert np.min(maps.measures(g, R)[0]) > 0


def test_cone_shrinks_with_the_torsion_range(g):
    n = maps.symmetry_axis(g)
    cones = [workspace.cone_from_curves(g, n, np.radians(s)) for s in (0, 20, 40, 80, 110)]
    assert all(np.diff(cones) < 0)


def test_figures_are_written(g, tmp_path):
    a = plots.maps_figure(g, tmp_path / "maps.png", torsions_deg=(-60.0, 0.0), n=25)
    general = s3.geometry(rcm_pin.load("spherical_3rrr", theta_12="70", theta_22="70"))
    c = plots.maps_figure(general, tmp_path / "general.png", torsions_deg=(0.0,), n=25)
    assert c.stat().st_size > 10_000
    b = plots.cone_figure(g, tmp_path / "cone.png", np.linspace(0, 180, 7), {0.0: 1.77})
    assert a.stat().st_size > 10_000 and b.stat().st_size > 10_000
    n = maps.symmetry_axis(g)
    pts = np.array(plots.slice_points(maps.singular_curves(g, n), 0.0))
    finite = pts[pts[:, 1] < np.pi - 1e-6, 1]  # σ = 0 meets the v_i = +u_i curves (red ×)
    assert len(finite) == 3  # linear interpolation between 721 curve samples: 1e-4 rad
    np.testing.assert_allclose(finite, workspace.cone_from_curves(g, n, 0.0), atol=1e-4)


@pytest.mark.parametrize("args", [{}, {"theta_12": "70"}])
def test_workspace_hook_reachable_share_and_cone(args):
    """The batched reachability of the hook against the per-orientation Δ of the inverse."""
    from rcm_pin.analysis import workspace as generic

    m = rcm_pin.load("spherical_3rrr", **args)
    g = s3.geometry(m)
    s = generic.summary(m, samples=500, seed=3)
    rots = random_rotations(np.random.default_rng(3), 500)
    share = np.mean([np.all(sc.leg_roots(g, r)[1] >= -sc.DELTA_TOL) for r in rots])
    assert s["reachable_share"] == share and (share == 1.0) == (not args)
    if not args:  # the Agile Eye: the cone of the curve route, 0 from 120° on
        n = maps.symmetry_axis(g)
        assert s["cone_deg_torsion_60"] == np.degrees(workspace.cone_from_curves(g, n, np.pi / 3))
        assert s["cone_deg_torsion_120"] == s["cone_deg_torsion_180"] == 0.0
    else:
        assert "cone_deg_torsion_0" not in s
