"""The two-mass model of paper 000: Pinocchio against the closed-form Lagrange forces."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.dynamics import tree as dy
from rcm_pin.errors import InvalidInputError, XacroArgumentError
from rcm_pin.mechanisms.rcm import two_mass as tm


@pytest.mark.parametrize(
    ("kwargs", "g"),
    [({}, None), ({}, (0.0, 0.0, -9.81)), ({"m": 0.7, "m_d": 0.3, "L": 0.15}, (1.0, -2.0, -9.0))],
)
def test_pinocchio_matches_closed_form(kwargs, g):
    mech = dy.with_gravity(
        rcm_pin.load("rcm_two_mass", **tm.two_mass_args(**kwargs), q3_upper=0.3), g
    )
    params = tm.TwoMassParams.of(mech)
    assert params.m == pytest.approx(kwargs.get("m", 0.4))
    assert pytest.approx(kwargs.get("L", 0.2)) == params.L
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(1000):
        q = rng.uniform(mech.lower, mech.upper)
        v, a = rng.normal(scale=2.0, size=3), rng.normal(scale=20.0, size=3)
        tau = dy.inverse_dynamics(mech, q, v, a)
        worst = max(
            worst,
            np.abs(tau - tm.generalized_forces(params, q, v, a)).max(),
            np.abs(tau - tm.dalembert_forces(params, q, v, a)).max(),
            np.abs(dy.mass_matrix(mech, q) - tm.mass_matrix(params, q)).max(),
        )
    assert worst < 1e-10


def test_catalogue_defaults():
    mech = rcm_pin.load("rcm_two_mass")
    params = tm.TwoMassParams.of(mech)
    assert params.m_d == pytest.approx(tm.reduced_mass(0.10, 0.15, 0.15)) == pytest.approx(0.2)
    assert mech.nq == 3 and mech.model_full.nq == 3
    assert "rcm_two_mass" in [s.name for s in rcm_pin.catalogue()]
    from rcm_pin.catalog.files import check_rendered

    assert "rcm_two_mass" not in check_rendered()


def test_errors():
    with pytest.raises(InvalidInputError, match=r"^v must be 3 finite numbers \(q1, q2, q3\)"):
        tm.generalized_forces(tm.TwoMassParams(), np.zeros(3), np.zeros(2), np.zeros(3))
    with pytest.raises(
        XacroArgumentError, match=r"^L=-0.1 is out of range for rcm_two_mass.urdf.xacro; valid: \("
    ):
        rcm_pin.load("rcm_two_mass", **tm.two_mass_args(L=-0.1))
