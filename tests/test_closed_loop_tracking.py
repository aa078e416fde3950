"""Computed-torque tracking of the planar 3-RRR platform (paper 004's control law)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rcm_pin.errors import InvalidInputError
from rcm_pin.studies.planar_tracking import (
    TrackingSettings,
    check_path,
    configuration,
    controller,
    error_response,
    reference_torques,
    simulate_tracking,
)

SHORT = TrackingSettings(duration=0.5, samples=51)


@pytest.fixture(scope="module")
def result(m3):
    return simulate_tracking(m3, SHORT)


def test_error_follows_the_linear_error_dynamics(result):
    """Perfect model: every output error obeys τ²ë + 2ζτė + e = 0 (closed form)."""
    np.testing.assert_allclose(result.error, error_response(result.t, SHORT), atol=1e-6)
    assert np.abs(result.error[0]).max() > 1e-3  # it starts off the reference


def test_closure_stays_closed(result):
    assert result.max_closure_residual < 1e-9


@pytest.mark.parametrize("zeta", [0.5, 1.0, 2.0])
def test_error_response_solves_the_ode(zeta):
    """The closed form against finite differences of τ²ë + 2ζτė + e."""
    s = dataclasses.replace(SHORT, zeta=zeta, rate_offset=(0.01, -0.02, 0.1))
    h = 1e-5
    t = np.linspace(0.01, 0.4, 40)
    e = error_response(t, s)
    ed = (error_response(t + h, s) - error_response(t - h, s)) / (2 * h)
    edd = (error_response(t + h, s) - 2 * e + error_response(t - h, s)) / h**2
    residual = s.tau**2 * edd + 2 * s.zeta * s.tau * ed + e
    np.testing.assert_allclose(residual, 0.0, atol=1e-6)
    np.testing.assert_allclose(error_response(np.zeros(1), s)[0], s.offset, atol=1e-15)


def test_control_on_the_reference_equals_inverse_dynamics(m3):
    """Second route: started exactly on the reference, the law gives the reference torques."""
    from rcm_pin.dynamics.constrained import velocity_for_output

    s = dataclasses.replace(SHORT, offset=(0.0, 0.0, 0.0))
    times = np.linspace(0.0, 0.4, 5)
    expected = reference_torques(m3, s, times)
    for t, tau_ref in zip(times, expected):
        p, pd, _ = s.reference(float(t))
        q = configuration(m3, p, s.mode)
        v = velocity_for_output(m3, q, pd)
        law = controller(m3, s)
        np.testing.assert_allclose(law.effort(float(t), q, v).tau, tau_ref, atol=1e-9)


def test_default_path_is_regular(m3):
    measures = check_path(m3, SHORT)
    assert min(measures.values()) > 0.1


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"tau": -1.0}, "tau -1.0 is invalid; valid: finite and > 0"),
        ({"samples": 1}, "samples 1 is invalid; valid: >= 2"),
        ({"mode": "xyz"}, "mode 'xyz' is not a working mode of planar_3rrr; valid: +++"),
    ],
)
def test_bad_settings(m3, change, message):
    with pytest.raises(InvalidInputError, match=message.replace("+", r"\+")):
        simulate_tracking(m3, dataclasses.replace(SHORT, **change))


def test_five_bar_is_refused(m5):
    with pytest.raises(
        InvalidInputError,
        match=r"platform tracking needs a closed mechanism with output \(x, y, rz\)",
    ):
        simulate_tracking(m5, SHORT)


def test_simulated_torques_started_on_the_reference_equal_inverse_dynamics(m3):
    """Second route on a whole run: no initial error, so the simulated drive torques are the
    closed-loop inverse dynamics of the exact reference (inverse position + velocity + ID)."""
    s = dataclasses.replace(SHORT, offset=(0.0, 0.0, 0.0), samples=11)
    run = simulate_tracking(m3, s)
    assert np.abs(run.error).max() < 1e-9
    np.testing.assert_allclose(run.torques, reference_torques(m3, s, run.t), atol=1e-9)
