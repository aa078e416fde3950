"""IK of closed mechanisms (ocp.ik, ocp.closure): the output coordinates with the loop
closures as equality constraints, against ``rcm_pin.inverse`` and Pinocchio's closures.

Mechanisms: the catalogue's planar_3rrr (x, y, rz), five_bar (x, y) and four_bar (rz),
all with 3d closures, and a four-bar cut in the middle of its coupler instead of at B
(one 6d weld closure, rows x, y, rz; generic family, numeric ``rcm_pin.inverse``).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp import IKProblem
from ocp.closure import closure_function, log3
from rcm_pin.catalog.files import render_default
from rcm_pin.errors import InvalidInputError

CLOSED = ("planar_3rrr", "five_bar", "four_bar")
TARGETS = {"planar_3rrr": [0.01, 0.02, 0.1], "five_bar": [0.02, 0.25], "four_bar": [1.0]}
CLOSURE_TOL = 1e-9  # Pinocchio closure residual of every accepted IK solution
MODE_TOL = 1e-7  # a solution is a working mode when its coordinates agree this well
_LIMIT = 'lower="-6.283185307179586" upper="6.283185307179586"'


def split_four_bar() -> rcm_pin.Mechanism:
    """four_bar with the coupler cut at its middle: a 6d weld (rows x, y, rz) between its
    halves, carried by A (crank side) and by a new joint B on the rocker."""
    head = render_default("four_bar").partition("<rcm_pin")[0]
    head = head.replace(
        '<link name="coupler_tip"/>',
        '<link name="coupler_tip"/><joint name="mid_a_joint" type="fixed"><parent link='
        '"coupler"/><child link="mid_a"/><origin xyz="0.0375 0 0" rpy="0 0 0"/></joint>'
        '<link name="mid_a"/>',
    )
    head = head.replace(
        '<link name="rocker_tip"/>',
        '<link name="rocker_tip"/><joint name="B" type="revolute"><parent link="rocker_tip"/>'
        f'<child link="half"/><axis xyz="0 0 1"/><limit effort="10" {_LIMIT} velocity="20"/>'
        '</joint><link name="half"><inertial><mass value="0.01"/><inertia ixx="1e-7" ixy="0" '
        'ixz="0" iyy="1e-7" iyz="0" izz="1e-7"/></inertial></link><joint name="mid_b_joint" '
        'type="fixed"><parent link="half"/><child link="mid_b"/><origin xyz="-0.0375 0 0" '
        'rpy="0 0 0"/></joint><link name="mid_b"/>',
    )
    element = (
        '<rcm_pin output_frame="rocker" output_coords="rz"><closed_loop frame_a="mid_a" '
        'frame_b="mid_b" type="6d" rows="x y rz"/><actuated joint="O1"/></rcm_pin></robot>'
    )
    return rcm_pin.from_urdf(head + element, "split_four_bar")


@pytest.fixture(scope="module", params=[*CLOSED, "split_four_bar"])
def closed(request):
    """(mechanism, target, its working modes from rcm_pin.inverse)."""
    if request.param == "split_four_bar":
        mech, target = split_four_bar(), TARGETS["four_bar"]
    else:
        mech, target = rcm_pin.load(request.param), TARGETS[request.param]
    return mech, np.array(target), rcm_pin.inverse(mech, target).solutions


def _wrapped(mech: rcm_pin.Mechanism, d: np.ndarray) -> np.ndarray:
    d = np.array(d, dtype=float)
    d[..., mech.revolute] = (d[..., mech.revolute] + np.pi) % (2 * np.pi) - np.pi
    return np.abs(d)


def _mode_of(mech, q, modes) -> tuple[str, float]:
    dist = [_wrapped(mech, mech.from_pin(q) - s.q).max() for s in modes]
    k = int(np.argmin(dist))
    return modes[k].mode, dist[k]


def test_log3_matches_pinocchio():
    rng = np.random.default_rng(3)
    r = ca.SX.sym("R", 3, 3)
    f = ca.Function("log3", [r], [log3(r)])
    for angle in (*rng.uniform(0.0, 3.0, 50), 1e-5, 1e-9, 1e-12, 0.0):
        axis = rng.normal(size=3)
        rot = pin.exp3(angle * axis / np.linalg.norm(axis))
        assert np.abs(np.array(f(rot)).ravel() - pin.log3(rot)).max() < 1e-12


def test_closure_residual_and_jacobian_match_pinocchio(closed):
    """3d: the residual equals Pinocchio's everywhere (1e-12); every kind: both vanish at
    the working modes and their Jacobians agree there (1e-10)."""
    mech, _, modes = closed
    fun = closure_function(IKProblem(mech).sm, mech.loops)
    jac = ca.Function("closure_jacobian", [fun.sx_in(0)], [ca.jacobian(fun(fun.sx_in(0)),
                                                                       fun.sx_in(0))])  # fmt: skip
    rng = np.random.default_rng(5)
    if all(c.kind == "3d" for c in mech.loops.closures):
        for q in rng.uniform(-np.pi, np.pi, size=(200, mech.nq)):
            qp = mech.to_pin(q)
            assert np.abs(np.array(fun(qp)).ravel() - mech.closure_residual(qp)).max() < 1e-12
    for s in modes:
        qp = mech.to_pin(s.q)
        e, j_pin = mech.residual_and_jacobian(qp)
        assert np.abs(np.array(fun(qp)).ravel()).max() < 1e-12 and np.abs(e).max() < 1e-12
        assert np.abs(np.array(jac(qp)) - j_pin).max() < 1e-10


def test_closed_ik_solutions_are_working_modes(closed):
    """From the home configuration and from random starts (IPOPT; SQP from home): every
    solution the NLP accepts closes the loops in Pinocchio to 1e-9, reaches the target
    and is one of the working modes of ``rcm_pin.inverse``."""
    mech, target, modes = closed
    prob = IKProblem(mech, seed=1)
    assert prob.mode == "output" and prob.default_solver == "ipopt"
    starts = [None] + [prob.random_configuration() for _ in range(40)]
    found: dict[str, int] = {}
    for k, q0 in enumerate(starts):
        for solver in ("ipopt", "sqpmethod") if k == 0 else ("ipopt",):
            res = prob.solve(target, q0, solver=solver, raise_on_failure=False)
            if not res.success:
                continue
            assert np.abs(mech.closure_residual(res.q)).max() <= CLOSURE_TOL
            assert res.closure_residual <= CLOSURE_TOL
            err = mech.output.error(mech.output_value(res.q), target)
            assert np.abs(err).max() < 1e-8
            mode, dist = _mode_of(mech, res.q, modes)
            assert dist < MODE_TOL, (mech.name, mode, dist)
            found[mode] = found.get(mode, 0) + 1
    print(f"\n{mech.name}: working modes found {found} of {len(modes)}")
    assert sum(found.values()) >= 10 and len(found) >= min(2, len(modes))


def test_split_four_bar_modes_are_the_four_bar_modes():
    """The 6d-welded four-bar reaches the same crank / coupler / rocker angles."""
    split, four = split_four_bar(), rcm_pin.load("four_bar")
    target = TARGETS["four_bar"]
    # from the neutral start (split's default home, assembled at mid-range, leads IPOPT
    # to a local minimum of this target)
    res = IKProblem(split).solve(target, q0=np.zeros(split.model.nq))
    q4 = split.from_pin(res.q)[:3]  # O1, A, O2 (B is the weld's new joint)
    dist = [_wrapped(four, q4 - s.q).max() for s in rcm_pin.inverse(four, target).solutions]
    assert min(dist) < MODE_TOL


def test_closed_ik_rejects_what_it_cannot_do():
    mech = rcm_pin.load("planar_3rrr")
    prob = IKProblem(mech)
    with pytest.raises(InvalidInputError, match="loop closures need 'ipopt'"):
        prob.solve(TARGETS["planar_3rrr"], solver="lm")
    with pytest.raises(InvalidInputError, match=r"\(3,\)"):
        prob.solve([0.01, 0.02])
    with pytest.raises(InvalidInputError, match="output"):
        IKProblem(mech.model, "platform_centre", mode="output")
