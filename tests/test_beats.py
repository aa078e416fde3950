"""Nonlinear free vibrations with beats (rcm_pin.studies.beats): energy, modal energies and
the beat period against 2π/|ω₃ − ω₁| of the frequency equation."""

from __future__ import annotations

import numpy as np

from rcm_pin.studies.beats import BeatSettings, run


def test_beats_energy_and_period():
    s = BeatSettings(beats=1.8, dt=5e-4)
    r = run(s)
    np.testing.assert_allclose(r.output[0] - r.equilibrium, [s.amplitude, 0.0, 0.0], atol=1e-12)
    assert r.energy_drift <= 1e-8  # acceptance (measured ~6e-11)
    # small amplitude (1e-4 m): within 1 % of the linear beat period (measured 6e-4)
    assert abs(r.beat_period() / r.linear_beat_period - 1.0) < 1e-2
    # the energy passes from x to y, z: their amplitude reaches > half of x's initial one
    assert np.max(np.abs(r.output[:, 1] - r.equilibrium[1])) > 0.5 * s.amplitude
    # linear limit: the modal energies stay constant to 1e-3 of the total
    spread = np.max(r.modal_energy, axis=0) - np.min(r.modal_energy, axis=0)
    assert np.all(spread < 1e-3 * r.energy[0])
    np.testing.assert_allclose(np.sum(r.modal_energy[0]), r.energy[0], rtol=1e-3)
