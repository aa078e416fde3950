"""Constrained dynamics, closed-loop inverse dynamics, drive switching on the five-bar."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.loop_velocity import passive_velocity
from rcm_pin.dynamics.constrained import (
    forward_dynamics,
    inverse_dynamics,
    pin_constraint_dynamics,
)
from rcm_pin.studies.five_bar_switching import StudySettings, simulate, torque_along_reference


@pytest.mark.parametrize(
    "name,pose", [("planar_3rrr", [0.02, -0.01, 0.2]), ("five_bar", [0.02, 0.2])]
)
def test_kkt_dynamics_matches_pin_constraint_dynamics(name, pose):
    m = rcm_pin.load(name)
    rng = np.random.default_rng(0)
    q = rcm_pin.inverse(m, np.array(pose)).solutions[1].q
    v = passive_velocity(m, q, rng.normal(size=m.loops.dof))
    tau = np.zeros(m.model.nv)
    tau[m.loops.drive_v] = rng.normal(size=m.loops.dof)
    a, lam = forward_dynamics(m, q, v, tau)
    assert np.max(np.abs(a - pin_constraint_dynamics(m, q, v, tau))) < 1e-9
    tau_back, lam_back = inverse_dynamics(m, q, v, a)
    assert np.allclose(tau_back, tau[m.loops.drive_v], atol=1e-10)
    assert np.allclose(lam_back, lam, atol=1e-10)


def test_main_drive_torque_blows_up_at_crossing_extra_stays_bounded(m5):
    ref = torque_along_reference(m5, StudySettings(), n=401)
    main = np.max(np.abs(ref["main"]), axis=1)
    extra = np.max(np.abs(ref["extra"]), axis=1)
    i = int(np.nanargmin(ref["measure"]))
    assert ref["measure"][i] < 1e-2
    # |τ| · measure stays O(1): |τ| ∝ 1/distance to the type-2 curve
    near = ref["measure"] < 0.05
    prod = main[near] * ref["measure"][near]
    assert np.nanmax(prod) / np.nanmin(prod) < 5.0
    far = ref["measure"] > 0.3
    assert np.nanmax(main) > 50 * np.nanmax(main[far])
    assert np.nanmax(extra[near]) < StudySettings().tau_max


def test_switching_keeps_efforts_bounded_and_tracking(m5):
    s = StudySettings(tau_max=0.5)
    free = simulate(m5, "main", False, None, s, max_step=1e-2)
    sat = simulate(m5, "main, saturated", False, s.tau_max, s, max_step=1e-2)
    sw = simulate(m5, "switching", True, s.tau_max, s, max_step=1e-2)
    for run in (free, sat, sw):
        assert run.completed
    late = sw.t > 0.3
    assert np.max(np.abs(free.tau_main)) > 10 * np.max(np.abs(sw.tau_main))
    assert np.max(np.abs(sw.tau_main)) < s.tau_max and np.max(np.abs(sw.tau_extra)) < s.tau_max
    assert sw.extras_on.any() and not sw.extras_on[-1]
    assert np.max(sw.error[late]) < 2e-6
    assert np.max(sat.error[sat.t > 0.3]) > 5 * np.max(sw.error[late])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda m, z: forward_dynamics(m, "abc", z, z),
            "q 'abc' is not numeric; valid: real numbers",
        ),
        (
            lambda m, z: forward_dynamics(m, np.zeros(m.model.nq), z, np.zeros(2)),
            "tau_full has shape (2,); valid: (4,) for five_bar (4 values)",
        ),
        (
            lambda m, z: inverse_dynamics(m, np.zeros(m.model.nq), z, np.full(4, np.nan)),
            "a has NaN or infinite entries: [nan, nan, nan, nan]",
        ),
        (
            lambda m, z: forward_dynamics(m, np.zeros(m.model.nq), np.full(4, 1e300), z),
            "v has an entry of magnitude 1e+300; valid: |value| <= 1e+06 (larger values are "
            "meaningless for a mechanism)",
        ),
    ],
    ids=["string q", "short tau", "NaN acceleration", "huge v"],
)
def test_constrained_dynamics_inputs_are_checked(call, message):
    from rcm_pin.errors import InvalidInputError

    mech = rcm_pin.load("five_bar")
    with pytest.raises(InvalidInputError) as exc:
        call(mech, np.zeros(mech.model.nv))
    assert str(exc.value) == message


@pytest.mark.parametrize("name", ["eye_4dof", "translational_3ppapa_loops"])
def test_redundant_closure_rows_give_the_second_routes_acceleration(name):
    """Over-constrained loops (J_c rank deficient: 11 rows of rank 8, 27 of rank 18) made
    the KKT matrix singular: eye_4dof's q̈ was off by 4.2e-3 relative, the 3-PPaPa raised
    LinAlgError. The KKT solve keeps an independent set; pin.constraintDynamics agrees."""
    from rcm_pin.dynamics.constrained import (
        forward_dynamics,
        pin_constraint_dynamics,
        world_closure,
    )

    mech = rcm_pin.load(name)
    q = mech.q_pin(mech.home)
    rng = np.random.default_rng(11)
    jc = world_closure(mech, q, np.zeros(mech.model.nv))[1]
    assert np.linalg.matrix_rank(jc) < jc.shape[0]
    basis = np.linalg.svd(jc)[2][np.linalg.matrix_rank(jc) :]
    for _ in range(3):
        v = basis.T @ rng.normal(size=len(basis))
        tau = rng.normal(size=mech.model.nv)
        acc = forward_dynamics(mech, q, v, tau, baumgarte=(0.0, 0.0))[0]
        ref = pin_constraint_dynamics(mech, q, v, tau)
        # 1e-9: the proximal solver of route 2 stops at its own tolerance
        assert np.abs(acc - ref).max() <= 1e-9 * max(np.abs(ref).max(), 1.0)
