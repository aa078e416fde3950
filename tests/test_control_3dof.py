"""Paper 004's control example on the translational 3-PPaPa (rcm_pin.studies.control_3dof):
the transient time, the error against the linear error dynamics, the model-mismatch table."""

from __future__ import annotations

import numpy as np
import pytest

from rcm_pin.studies.control_3dof import (
    BAND,
    ControlSettings,
    linear_error,
    mismatch_table,
    run,
    settling_factor,
    tau_for_transient,
)

#: A short run over the transient: 0.06 s is the 25th of 61 samples.
SHORT = ControlSettings(duration=0.15, samples=61)


@pytest.fixture(scope="module")
def short_run():
    return run(SHORT)


def test_transient_definition():
    s = settling_factor()
    assert abs((1.0 + s) * np.exp(-s) - BAND) < 1e-15
    tau = tau_for_transient(0.06)
    np.testing.assert_allclose(tau, 0.06 / s, rtol=1e-15)
    t = np.linspace(0.06, 1.0, 2001)
    ratio = np.abs(linear_error(t, SHORT)) / np.abs(np.array(SHORT.offset))
    np.testing.assert_allclose(ratio[0], BAND, rtol=1e-9)
    assert np.all(ratio[1:] < BAND) and np.all(np.diff(ratio, axis=0) < 0)


def test_error_follows_linear_error_dynamics(short_run):
    np.testing.assert_allclose(short_run.error[0], SHORT.offset, atol=1e-12)
    assert short_run.linear_deviation(SHORT) < 1e-9  # [m], acceptance
    assert short_run.closure_residual < 1e-10
    i = int(np.argmin(np.abs(short_run.t - 0.06)))
    assert abs(short_run.t[i] - 0.06) < 1e-12
    np.testing.assert_allclose(
        np.abs(short_run.error[i]) / np.abs(np.array(SHORT.offset)), BAND, rtol=1e-6
    )
    assert abs(short_run.transient_time() - 0.06) < 1e-4  # 2.5 ms samples, linear interpolation


def test_mismatch_rows():
    s = ControlSettings(duration=0.08, samples=33)
    rows = mismatch_table(s, {"perfect model": {}, "output mass +10 %": {"m_platform": "0.55"}})
    assert rows[0]["change_percent"] == 0.0
    assert 0.0 < rows[1]["change_percent"] < 100.0
    assert rows[1]["peak_force_N"] > 0.0 and np.isfinite(rows[1]["error_after_transient_mm"])
