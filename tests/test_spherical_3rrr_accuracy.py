"""Spherical 3-RRR accuracy: paper 004's linear theory (Cramer, with the δα misprints) vs the
nonlinear recomputation.

Routes: closed-form derivatives against complex step; Cramer against ``np.linalg.solve``;
the nonlinear change (Newton on the perturbed loop equations) against Pinocchio (the generic
joint-placement errors re-solved on the closures) for link-angle errors, and against the
family's closed-form direct problem for drive errors.
"""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.analysis.accuracy import placement_change
from rcm_pin.cli import main
from rcm_pin.mechanisms import spherical_3rrr as s3
from rcm_pin.mechanisms.spherical_3rrr import accuracy as acc
from rcm_pin.mechanisms.spherical_3rrr import closed_form as sc
from rcm_pin.rotations import random_rotations, rpy_to_matrix

X = np.array([0.3, 0.4, 0.5])  # α, β, γ [rad]: the pose of the report
DELTA = np.radians(0.5)  # [rad]
STEP = 1e-30  # complex step [rad]


@pytest.fixture(scope="module")
def mech():
    return rcm_pin.load("spherical_3rrr")


@pytest.fixture(scope="module")
def g(mech):
    return s3.geometry(mech)


def _pose(g, x, mode=0):
    R = rpy_to_matrix(*x)
    return R, sc.inverse_position(g, R)[mode]


def test_loop_equations_vanish_and_derivatives_match_complex_step(g):
    rng = np.random.default_rng(3)
    for R in random_rotations(rng, 10):
        x = np.array(rcm_pin.rotations.matrix_to_rpy(R))
        for mode in (0, 3, 6):
            p = acc.variables(g, sc.inverse_position(g, R)[mode])
            assert np.max(np.abs(acc.residual(g, x, p, g.v0))) < EXACT
            jx = np.column_stack(
                [np.imag(acc.residual(g, x + 1j * STEP * e, p, g.v0)) / STEP for e in np.eye(3)]
            )
            jp = np.column_stack(
                [np.imag(acc.residual(g, x + 0j, p + 1j * STEP * e, g.v0)) / STEP
                 for e in np.eye(9)]
            )  # fmt: skip
            np.testing.assert_allclose(acc.output_jacobian(g, x, p, g.v0), jx, atol=EXACT)
            np.testing.assert_allclose(acc.error_jacobian(g, x, p, g.v0), jp, atol=EXACT)


def test_cramer_corrected_solves_and_the_printed_delta_alpha_does_not(g):
    _, phi = _pose(g, X)
    p = acc.variables(g, phi)
    J, dF = acc.output_jacobian(g, X, p, g.v0), acc.error_jacobian(g, X, p, g.v0)
    for k in range(9):
        W = -dF[:, k] * DELTA
        exact = np.linalg.solve(J, W)
        np.testing.assert_allclose(acc.linear_error(J, W), exact, atol=EXACT)
        np.testing.assert_allclose(acc.cramer_delta_alpha(J, W), exact[0], atol=EXACT)
        printed = acc.cramer_delta_alpha(J, W, printed=True)
        assert abs(printed - exact[0]) > 0.05 * abs(exact[0])


def test_the_two_misprints_are_exactly_the_printed_differences():
    """Corrected: numerator det J_1, denominator det J. Printed minus corrected is exactly
    F2β (F2γ − F3γ) W1 (numerator) and −(F1β − F1α) F2γ F3β (denominator): one index
    misprint in each (random J, W; Fiβ = J[i−1, 1])."""
    rng = np.random.default_rng(4)
    for _ in range(20):
        J, W = rng.standard_normal((3, 3)), rng.standard_normal(3)
        j1 = J.copy()
        j1[:, 0] = W
        num, den = acc.cramer_terms(J, W)
        np.testing.assert_allclose([num, den], [np.linalg.det(j1), np.linalg.det(J)],
                                   rtol=1e-12, atol=EXACT)  # fmt: skip
        pnum, pden = acc.cramer_terms(J, W, printed=True)
        np.testing.assert_allclose(pnum - num, J[1, 1] * (J[1, 2] - J[2, 2]) * W[0], atol=EXACT)
        np.testing.assert_allclose(pden - den, -(J[0, 1] - J[0, 0]) * J[1, 2] * J[2, 1],
                                   atol=EXACT)  # fmt: skip


@pytest.mark.parametrize(("joint", "component", "column"),
                         [("w1", 3, 0), ("w2", 3, 1), ("w3", 3, 2),
                          ("v1", 4, 3), ("v2", 4, 4), ("v3", 4, 5)])  # fmt: skip
def test_nonlinear_link_angle_error_matches_pinocchio(mech, g, joint, component, column):
    R, phi = _pose(g, X)
    p = acc.variables(g, phi)
    dp = np.zeros(9)
    dp[column] = DELTA
    dx = acc.nonlinear_error(g, X, p, dp, g.v0)
    # a turn −δ of the placement of w_i about x (v_i about y) is δθ_i1 (δθ_i2) = +δ
    e = placement_change(mech, s3.full_q(mech, R, phi), joint, component)(-DELTA)
    np.testing.assert_allclose(pin.log3(rpy_to_matrix(*(X + dx)) @ R.T), e, atol=EXACT)


@pytest.mark.parametrize("leg", [0, 1, 2])
def test_nonlinear_drive_error_matches_the_direct_problem(g, leg):
    R, phi = _pose(g, X)
    dp = np.zeros(9)
    dp[6 + leg] = DELTA
    dx = acc.nonlinear_error(g, X, acc.variables(g, phi), dp, g.v0)
    modes = sc.direct_position(g, phi + dp[6:])
    nearest = min(modes, key=lambda r: np.linalg.norm(r - R))
    np.testing.assert_allclose(rpy_to_matrix(*(X + dx)), nearest, atol=EXACT)


def test_linear_theory_error_is_second_order(g):
    """The relative difference of linear and nonlinear halves with the error size."""
    _, phi = _pose(g, X)
    big = acc.table(g, X, phi, DELTA)
    small = acc.table(g, X, phi, DELTA / 2)
    for b, s in zip(big, small, strict=True):
        ratio = s["relative_difference"] / b["relative_difference"]
        assert 0.45 < ratio < 0.55 and b["relative_difference"] < 0.02


def test_accuracy_hook_through_the_cli(capsys):
    code = main(["accuracy", "spherical_3rrr", "--json"])
    payload = json.loads(capsys.readouterr().out)
    assert code == 0 and [r["joint"] for r in payload["rows"]] == list(acc.PARAMETERS)
    for r in payload["rows"]:
        assert r["relative_difference"] < 0.02
        np.testing.assert_allclose(r["delta_alpha_corrected"], r["linear"][0], atol=EXACT)
