"""Singularity detection: SVD rank vs the named-cause classifier, paper 003's claims."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis import singularity as sg
from rcm_pin.analysis.velocity import tool_jacobian
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm import singularity as rsg
from rcm_pin.mechanisms.rcm.closed_form import wrist_type

NAMES = ("rcm_bevel", "rcm_bevel_4dof", "rcm_belt", "rcm_bevel_rpy")


@pytest.fixture(scope="module", params=NAMES)
def mech(request):
    if request.param == "rcm_bevel_rpy":
        return rcm_pin.load("rcm_bevel", wrist_type="rpy")
    return rcm_pin.load(request.param)


def _agree(mech, q):
    J = tool_jacobian(mech, q)
    for task, Jt in (("full", J), ("position", J[:3])):
        svd = sg.analyse_jacobian(Jt, task)
        assert svd.singular == rsg.is_singular_closed_form(mech, q, task), (task, q)


def test_classifier_agrees_with_rank_on_random_configs(mech):
    rng = np.random.default_rng(7)
    n = 10_000 if mech.name == "rcm_bevel" else 2500
    lo = np.r_[-np.pi, -np.pi, -0.15, -np.pi, -np.pi, -np.pi][: mech.nq]
    for q in rng.uniform(lo, -lo, size=(n, mech.nq)):
        _agree(mech, q)


def _singular_sets(mech):
    sets = [(2, 0.0), (1, np.pi / 2), (1, -np.pi / 2)]
    if wrist_type(mech) == "zyz":
        sets += [(4, 0.0), (4, np.pi)]
    if wrist_type(mech) == "rpy":
        sets += [(4, np.pi / 2), (4, -np.pi / 2)]
    return sets


def test_classifier_on_and_near_each_singular_set(mech):
    rng = np.random.default_rng(8)
    base = rng.uniform(-1.2, 1.2, size=(40, mech.nq))
    base[:, 2] = rng.uniform(0.05, 0.12, 40)
    for q0 in base:
        for k, val in _singular_sets(mech):
            for d in (0.0, 1e-6, -1e-6):
                q = q0.copy()
                q[k] = val + d
                _agree(mech, q)
                if d == 0.0:
                    assert rsg.classify(mech, q)
                # two causes at once
                q2 = q.copy()
                q2[2] = 0.0
                _agree(mech, q2)


def test_rank_values_and_null_space():
    mech = rcm_pin.load("rcm_bevel")
    q = np.array([0.3, 0.2, 0.0, 0.1, 0.5, 0.2])
    a = sg.analyse(mech, q, "position")
    assert (a.rank, a.full_rank) == (1, 3)
    J = tool_jacobian(mech, q)[:3]
    assert np.abs(J @ a.null_space).max() < 1e-12
    assert a.null_space.shape == (6, 5)
    # the only reachable direction is the output axis e4
    e4 = rcm_pin.mechanisms.rcm.closed_form.output_axis(0.3, 0.2)
    assert np.abs(a.unreachable.T @ e4).max() < 1e-12
    f = sg.analyse(mech, np.array([0.3, np.pi / 2, 0.08, 0.1, 0.5, 0.2]))
    assert (f.rank, f.condition, f.manipulability < 1e-15) == (5, float("inf"), True)
    reg = sg.analyse(mech, np.array([0.3, 0.2, 0.08, 0.1, 0.5, 0.2]))
    assert reg.rank == 6 and np.isclose(
        reg.manipulability, abs(np.linalg.det(tool_jacobian(mech, [0.3, 0.2, 0.08, 0.1, 0.5, 0.2])))
    )
    # det J = q3^2 cos q2 sin q5 (zyz)
    assert np.isclose(reg.manipulability, 0.08**2 * np.cos(0.2) * np.sin(0.5))


def test_paper_claims_by_rank():
    verdicts = {c["claim"]: c["verdict"] for c in rsg.paper_claims(rcm_pin.load("rcm_bevel"))}
    assert verdicts == {
        "q3 = 0": "mechanism singularity",
        "q1 = +pi/2": "not a singularity",
        "q1 = -pi/2": "not a singularity",
        "q2 = +pi/2": "mechanism singularity",
        "q2 = -pi/2": "mechanism singularity",
    }


def test_grid_and_errors():
    mech = rcm_pin.load("rcm_bevel_4dof")
    xs, ys, m = sg.grid(mech, [0, 0, 0.08, 0], 0, 1, n=5, task="position")
    assert m.shape == (5, 5) and np.all(m > 0)
    assert np.isclose(m[2, 2], 0.08**2)
    with pytest.raises(InvalidInputError) as exc:
        sg.grid(mech, [0, 0, 0.08, 0], 1, 1)
    assert str(exc.value) == "grid coordinates 2,2; valid: two different numbers in 1..4"
    with pytest.raises(InvalidInputError) as exc:
        sg.analyse(mech, [0, 0, 0.08, 0], task="orientation")
    assert str(exc.value) == "task 'orientation'; valid: full, position"
