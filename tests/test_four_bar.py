"""The planar four-bar crank–rocker (paper 002's pitch drive): closed form vs Pinocchio.

Routes cross-checked: the family's closed form (rcm_pin/mechanisms/four_bar.py), Pinocchio's
closures through the generic position / velocity / singularity / dynamics code, the numeric
multistart and continuation routes, the screw route, finite differences, and independent
constructions of the singular sets written here (law of cosines, no call into the family).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, SOLVER
from scipy.integrate import solve_ivp

import rcm_pin
from rcm_pin.analysis.closed_position import direct_position_multistart, direct_position_path
from rcm_pin.analysis.loop_velocity import classify, passive_velocity, velocity_matrices
from rcm_pin.analysis.screws import screw_test
from rcm_pin.analysis.singularity_model import singularity_model
from rcm_pin.analysis.workspace import workspace_model
from rcm_pin.design.metrics import metric_source
from rcm_pin.dynamics.constrained import forward_dynamics, inverse_dynamics, pin_constraint_dynamics
from rcm_pin.errors import (
    InvalidInputError,
    SingularConfigurationError,
    UnreachablePoseError,
    XacroArgumentError,
)
from rcm_pin.linkage.fourbar import FourBar, performance
from rcm_pin.mechanisms import four_bar as fb
from rcm_pin.rotations import wrap_angle

#: (frame, crank, coupler, rocker) [m]: Grashof, crank–rocker, type-1 / type-2 poses built here.
LINKS = {
    "default": ((0.05419, 0.01788, 0.075, 0.05), True, True, 4, 0),  # paper 002: crank shortest
    "non_grashof": ((0.05, 0.035, 0.04, 0.03), False, False, 2, 2),  # s + l > p + q
    "rocker_crank": ((0.05, 0.04, 0.045, 0.02), True, False, 0, 4),  # rocker shortest
    "double_crank": ((0.02, 0.04, 0.05, 0.045), True, False, 0, 0),  # frame shortest
    "double_rocker": ((0.05, 0.04, 0.025, 0.045), True, False, 4, 4),  # coupler shortest
}

#: The xacro arguments of the four link lengths [m].
LINK_ARGS = ("frame", "crank", "coupler", "rocker")


def load(name="default"):
    return rcm_pin.load("four_bar", **dict(zip(LINK_ARGS, LINKS[name][0], strict=True)))


@pytest.fixture(scope="module")
def m4():
    return rcm_pin.load("four_bar")


@pytest.fixture(scope="module")
def g4(m4):
    return fb.geometry(m4)


def points(m, q):
    """Pinocchio positions (x, y) [m] of A, B on the rocker, O2 and B on the coupler."""
    pin.framesForwardKinematics(m.model, m.data, q)
    joint, frame = m.data.oMi, m.data.oMf
    a, o2 = (joint[m.model.getJointId(j)].translation[:2].copy() for j in ("A", "O2"))
    b, bc = (frame[m.frame_id(f)].translation[:2].copy() for f in ("rocker_tip", "coupler_tip"))
    return a, b, o2, bc


def cross(u, v):
    return float(u[0] * v[1] - u[1] * v[0])


def on_circles(r0, r1, d):
    """Angles ±α at the first centre of the points at r0, r1 from two centres d apart."""
    c = (d * d + r0 * r0 - r1 * r1) / (2.0 * d * r0)
    return [] if abs(c) > 1.0 else [np.arccos(c), -np.arccos(c)]


def type1_configs(g):
    """(q1, ψ) with crank and coupler aligned: |O1 B| = l1 + l2 or |l2 − l1|."""
    out = []
    for r, flip in ((g.l1 + g.l2, False), (abs(g.l2 - g.l1), g.l2 > g.l1)):
        for alpha in on_circles(r, g.l3, g.l0):
            b = r * np.array([np.cos(alpha), np.sin(alpha)])
            out.append((float(wrap_angle(alpha + np.pi * flip)), np.arctan2(b[1], b[0] - g.l0)))
    return out


def type2_configs(g):
    """(q1, ψ, μ) with coupler and rocker aligned: |A O2| = l2 + l3 (μ = π) or |l2 − l3|."""
    out, o2 = [], np.array([g.l0, 0.0])
    for r, mu in ((g.l2 + g.l3, np.pi), (abs(g.l2 - g.l3), 0.0)):
        for beta in on_circles(g.l1, r, g.l0):
            a = g.l1 * np.array([np.cos(beta), np.sin(beta)])
            b = o2 + (1.0 if mu or g.l3 > g.l2 else -1.0) * g.l3 * (a - o2) / r
            out.append((beta, np.arctan2(b[1], b[0] - g.l0), mu))
    return out


def paper_ab(m, q):
    """The family's A, B (the paper's, normalised) at q."""
    ab = singularity_model(m).ab_matrices(m, q)
    assert ab.paper
    return ab.A, ab.B


def random_configs(g, n, seed):
    """Every assembly mode at n random crank angles."""
    cranks = np.random.default_rng(seed).uniform(-np.pi, np.pi, n)
    return [fb.full_q(g, t, p) for t in cranks for p in fb.direct_position(g, t)]


# ------------------------------------------------------------------- position problems
def test_forward_both_assembly_modes_equal_the_closed_form(m4, g4):
    """721 crank angles; the first mode (B above A → O2) is the family's ``home`` at q1 = 0."""
    for q1 in np.linspace(-np.pi, np.pi, 721)[:-1]:
        res = rcm_pin.forward(m4, [q1], all_modes=True)
        psis = fb.direct_position(g4, q1)
        assert res.count == len(psis) == 2
        for i, (sol, psi) in enumerate(zip(res.solutions, psis, strict=True)):
            assert sol.mode == f"assembly_{i}" and sol.within_limits
            assert sol.residual <= EXACT and np.linalg.norm(m4.closure_residual(sol.q)) <= EXACT
            assert np.max(np.abs(wrap_angle(sol.q - fb.full_q(g4, q1, psi)))) < EXACT
            assert abs(wrap_angle(sol.output[0] - psi)) < EXACT
            a, b, o2, b_coupler = points(m4, sol.q)  # the closed form's points, |A B| = l2
            assert np.max(np.abs(a - g4.l1 * np.array([np.cos(q1), np.sin(q1)]))) < EXACT
            assert np.max(np.abs(b - o2 - g4.l3 * np.array([np.cos(psi), np.sin(psi)]))) < EXACT
            assert np.max(np.abs(b - b_coupler)) < EXACT and abs(np.hypot(*(b - a)) - g4.l2) < EXACT
            # documented order: B left of the line A → O2 first, then its mirror image
            assert (cross(o2 - a, b - a) > 0) == (i == 0)
    home, first = m4.home, rcm_pin.forward(m4, [0.0]).solutions[0]
    assert home[0] == 0.0 and home[2] > 0 and np.max(np.abs(wrap_angle(first.q - home))) < EXACT


def test_inverse_then_forward_round_trip_both_working_modes(m4, g4):
    rng = np.random.default_rng(10)
    lo, hi = sorted(p for _, p in type1_configs(g4) if p > 0)  # the swing of B above O1 O2
    # 1e-6 rad margin: at the extremes the working modes merge (type 1)
    psis = rng.uniform(lo + 1e-6, hi - 1e-6, 1000) * rng.choice([-1.0, 1.0], 1000)
    for psi in psis:
        inv = rcm_pin.inverse(m4, [psi])
        cranks = fb.inverse_position(g4, psi)
        assert [s.mode for s in inv.solutions] == list(fb.MODES) and len(cranks) == 2
        for sol, q1 in zip(inv.solutions, cranks, strict=True):
            assert sol.residual < EXACT and abs(wrap_angle(sol.output[0] - psi)) < 1e-10
            assert abs(wrap_angle(sol.q[0] - q1)) < 1e-10
            a, b, _, _ = points(m4, sol.q)
            assert (cross(b, a) > 0) == (sol.mode == "+")  # "+": A left of O1 → B
            fwd = rcm_pin.forward(m4, [sol.q[0]], all_modes=True)
            assert min(abs(wrap_angle(s.output[0] - psi)) for s in fwd.solutions) < 1e-10


def test_numeric_multistart_finds_the_closed_form_modes(m4, g4):
    for q1 in np.random.default_rng(11).uniform(-np.pi, np.pi, 12):
        numeric = direct_position_multistart(m4, [q1], n_starts=16, seed=3)
        closed = rcm_pin.forward(m4, [q1], all_modes=True)
        assert numeric.count == closed.count == 2
        for s in closed.solutions:
            assert min(np.max(np.abs(wrap_angle(s.q - t.q))) for t in numeric.solutions) < SOLVER


def test_mobility_rank_chebyshev_and_spatial_count(m4, g4):
    mob = rcm_pin.mobility(m4)
    assert mob.rank_mobility == 1 and mob.chebyshev == 1  # 3·3 − 2·(3 revolute + 1 at B)
    assert mob.n == 3 and mob.pairs == {5: 3, 1: 0, 3: 1}
    # Somov–Malyshev counts the cut pair B (a point coincidence) as a spherical pair,
    # class 3, in space: W = 6·3 − 5·3 − 3·1 = 0. All four axes are parallel to z, so the
    # out-of-plane coincidence (z of B) holds for every q: one of the counted constraints
    # is redundant and the rank count exceeds the formula by one (a planar loop counted in
    # space; with B as a revolute pair, class 5, it would be −2 with 3 redundant).
    assert mob.W == 0 and mob.redundant == 1 and mob.formula() == "W = 6·3 − 5·3 − 3·1 = 0"
    for q1 in np.random.default_rng(12).uniform(-np.pi, np.pi, 5):
        q = fb.full_q(g4, q1, fb.direct_position(g4, q1)[1])
        assert rcm_pin.mobility(m4, q).rank_mobility == 1


# --------------------------------------------------------------- velocity, singularities
def test_rocker_velocity_pinocchio_vs_closed_form_and_finite_differences(m4, g4):
    rng = np.random.default_rng(13)
    h = 1e-5
    for q1 in rng.uniform(-np.pi, np.pi, 100):
        for psi in fb.direct_position(g4, q1):
            q = fb.full_q(g4, q1, psi)
            (a_cf,), (b_cf,) = (x[0] for x in fb.ab_matrices(g4, q1, psi))
            vm, rate = velocity_matrices(m4, q), rng.normal()
            psid, psid_cf = (vm.output_jacobian() @ [rate])[0], -b_cf / a_cf * rate
            assert abs(psid - psid_cf) < SOLVER * max(1.0, abs(psid_cf))
            # A, B are known up to a common left factor: B/A is not
            assert abs(vm.B[0, 0] / vm.A[0, 0] - b_cf / a_cf) < SOLVER
            (a_h,), (b_h,) = (x[0] for x in paper_ab(m4, q))  # normalised
            assert abs(a_h - a_cf / (2 * g4.l2 * g4.l3)) < EXACT
            assert abs(b_h - b_cf / (2 * g4.l1 * g4.l2)) < EXACT
            assert abs(abs(a_h) - np.sin(fb.transmission_angle(g4, q1))) < EXACT  # |A| = sin μ
    # finite differences of the forward problem on the same assembly mode; 1e-6: Newton
    # stops at a closure residual ~1e-12 m, i.e. ~1e-11 rad in ψ, divided by 2h = 2e-5
    for q1, psi in [(0.3, fb.direct_position(g4, 0.3)[0]), (-2.0, fb.direct_position(g4, -2.0)[1])]:
        q = fb.full_q(g4, q1, psi)
        plus, minus = (rcm_pin.forward(m4, [q1 + s], q_guess=q).solutions[0] for s in (h, -h))
        fd = wrap_angle(plus.output[0] - minus.output[0]) / (2 * h)
        assert abs(fd - velocity_matrices(m4, q).output_jacobian()[0, 0]) < 1e-6
        qd = passive_velocity(m4, q, np.array([1.0]))
        assert np.max(np.abs(qd - wrap_angle(plus.q - minus.q) / (2 * h))) < 1e-6


def measures(m, q):
    """[type-2, type-1] × [closed form |A|, |B| (hook), Pinocchio |Ã|, |B̃| (A/L, B/L, absolute:
    N is orthonormal), screws ‖W·T‖ and the crank leg's σ_5/σ_1]; 0 on the singular set."""
    (a_h,), (b_h,) = (x[0] for x in paper_ab(m, q))
    vm, st, length = velocity_matrices(m, q), screw_test(m, q), m.loops.length_scale
    return np.abs([[a_h, vm.A[0, 0] / length, np.linalg.norm(st.W)],
                   [b_h, vm.B[0, 0] / length, st.leg_measures[0]]])  # fmt: skip


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")  # B̃ = 0 → 0/0
@pytest.mark.parametrize("name", LINKS)
def test_singular_sets_closed_form_pinocchio_and_screws(name):
    """Type 1 (crank ∥ coupler: B = 0, the rocker's extremes) and type 2 (coupler ∥ rocker:
    A = 0, transmission angle 0 or π) on the poses built here, and random poses."""
    m = load(name)
    g = fb.geometry(m)
    t1, t2 = type1_configs(g), type2_configs(g)
    assert (len(t1), len(t2)) == LINKS[name][3:]
    for kind, configs in ((1, [(*c, None) for c in t1]), (0, t2)):
        for q1, psi, mu in configs:
            q = fb.full_q(g, q1, psi)
            assert np.linalg.norm(m.closure_residual(q)) < EXACT
            meas = measures(m, q)
            assert np.max(meas[kind]) < EXACT  # and the other set is far (they never meet here)
            assert np.min(meas[1 - kind]) > 0.01
            if mu is not None:
                assert abs(np.cos(fb.transmission_angle(g, q1)) - np.cos(mu)) < EXACT
    for q in random_configs(g, 200, seed=14):
        assert np.min(measures(m, q)) > 1e-6  # no random pose within 1e-6 of a set


@pytest.mark.parametrize("name", ["default", "rocker_crank"])
def test_classifier_and_screw_flags_on_singular_sets(name):
    m = load(name)
    g = fb.geometry(m)
    poses = [(fb.full_q(g, q1, psi), "type 1") for q1, psi in type1_configs(g)]
    poses += [(fb.full_q(g, q1, psi), "type 2") for q1, psi, _ in type2_configs(g)]
    poses += [(q, "regular") for q in random_configs(g, 50, seed=15)]
    for q, label in poses:
        st = screw_test(m, q)
        assert classify(m, q).label == label
        assert (st.type1, st.type2) == (label == "type 1", label == "type 2")
        if label == "type 2":
            with pytest.raises(SingularConfigurationError):
                velocity_matrices(m, q).output_jacobian()


# ------------------------------------------------------------ rocker swing, Grashof class
def test_rocker_swing_by_continuation_and_transmission_angle(m4, g4):
    grid = np.linspace(-np.pi, np.pi, 3601)
    path = np.sort(np.r_[grid, [q1 for q1, psi in type1_configs(g4) if psi > 0]])
    on_grid = np.isin(path, grid)
    q0 = fb.full_q(g4, -np.pi, fb.direct_position(g4, -np.pi)[0])
    qs = direct_position_path(m4, path[:, None], q0)
    assert np.max(np.abs(qs[:, 0] - path)) < EXACT
    assert max(np.linalg.norm(m4.closure_residual(q)) for q in qs) < EXACT
    assert np.max(np.abs(wrap_angle(qs[-1] - qs[0]))) < SOLVER  # a full turn closes
    lo, hi = fb.rocker_range(g4)  # closed form: the dead centres, |O1 B| = l2 ∓ l1
    # the exact extremes are the type-1 (toggle) positions of the path
    exact = sorted(psi for _, psi in type1_configs(g4) if psi > 0)
    assert abs(exact[0] - lo) < EXACT and abs(exact[1] - hi) < EXACT
    assert abs(qs[:, 2].min() - lo) < SOLVER and abs(qs[:, 2].max() - hi) < SOLVER
    # a grid of crank angles can only miss them inwards: error ≤ ½ |ψ''| (Δ/2)² with
    # Δ = 2π/3600 and |ψ''| < 2 rad/rad² here, i.e. below 7.7e-7 rad
    assert 0.0 <= qs[on_grid, 2].min() - lo < 7.7e-7 and 0.0 <= hi - qs[on_grid, 2].max() < 7.7e-7
    mus = []
    for a, b, o2, _ in (points(m4, q) for q in qs):  # angle A–B–O2, atan2 form
        mus.append(np.arctan2(abs(cross(a - b, o2 - b)), (a - b) @ (o2 - b)))
    assert np.max(np.abs(np.array(mus) - fb.transmission_angle(g4, path))) < EXACT
    summary = workspace_model(m4).summary(m4, None, 0)
    assert abs(summary["swing"] - (hi - lo)) < EXACT and summary["crank_rocker"]
    assert abs(summary["transmission_angle_min"] - min(np.array(mus)[on_grid])) < EXACT


def test_grashof_hand_picked_and_against_full_turns():
    """LINKS, then Grashof's theorem on 500 random link sets (no ties): the crank (rocker)
    turns fully iff Grashof with the crank (rocker) or the frame shortest; a full turn is
    read off the closed forms at 0 and π, where |A O2| (|O1 B|) is extremal."""
    for lengths, grashof, crank_rocker, _, _ in LINKS.values():
        g = fb.GeometryFourBar(*lengths)
        assert (g.grashof, g.crank_rocker) == (grashof, crank_rocker)
    kinds = set()
    for lengths in np.random.default_rng(16).uniform(0.01, 0.1, (500, 4)):
        g = fb.GeometryFourBar(*lengths)
        crank = all(fb.direct_position(g, t) for t in (0.0, np.pi))
        rocker = all(fb.inverse_position(g, t) for t in (0.0, np.pi))
        shortest = int(np.argmin(lengths))
        assert crank == (g.grashof and shortest in (0, 1))
        assert rocker == (g.grashof and shortest in (0, 3))
        assert g.crank_rocker == (crank and not rocker)
        kinds.add((crank, rocker, g.grashof))
    assert len(kinds) == 5  # crank–rocker, rocker–crank, double crank, double rocker, non-Grashof


@pytest.mark.parametrize(
    ("lengths", "kind"),
    [
        ((3.0, 1.0, 2.0, 2.0), "change-point"),  # s + l = p + q, the crank strictly shortest
        ((0.05, 0.03, 0.05, 0.03), "change-point"),  # a parallelogram
        ((0.05419, 0.01788, 0.075, 0.05), "crank-rocker"),  # s + l < p + q, crank shortest
        ((0.05, 0.035, 0.04, 0.03), "non-Grashof triple-rocker"),  # s + l > p + q
    ],
)
def test_one_grashof_rule_for_the_family_and_the_linkage(lengths, kind):
    """The family's geometry is the linkage layer's four-bar: one class, one crank–rocker
    verdict (a change-point linkage is none), the same in the family's metrics."""
    mech = rcm_pin.load("four_bar", **dict(zip(LINK_ARGS, (str(v) for v in lengths))))
    g = fb.geometry(mech)
    assert g == FourBar(*lengths)
    crank_rocker = kind == "crank-rocker"
    assert g.grashof_class == kind and g.crank_rocker == crank_rocker
    assert g.grashof == (kind != "non-Grashof triple-rocker")
    assert performance(g).crank_rocker == crank_rocker
    swing = metric_source(mech.family).metrics()["swing"].evaluate(mech)
    if crank_rocker:
        lo, hi = fb.rocker_range(g)
        assert workspace_model(mech).summary(mech, None, 0)["crank_rocker"]
        assert abs(swing - np.rad2deg(hi - lo)) < EXACT
    else:
        assert np.isnan(swing)
        assert message(InvalidInputError, workspace_model(mech).summary, mech, None, 0) == (
            f"links {tuple(lengths)} [m] are a {kind} linkage, not a crank-rocker; valid: "
            "Grashof (s + l < p + q) with the crank strictly the shortest link"
        )


# ------------------------------------------------------------------------------ dynamics
def test_kkt_dynamics_vs_pinocchio_and_inverse_dynamics(m4, g4):
    rng = np.random.default_rng(17)
    for q in random_configs(g4, 6, seed=18):
        v = passive_velocity(m4, q, 5.0 * rng.normal(size=1))
        tau = np.zeros(m4.nv)
        tau[m4.loops.drive_v] = 1e-3 * rng.normal()  # [N·m]: |q̈| ~ 10..200 rad/s²
        a, lam = forward_dynamics(m4, q, v, tau)
        assert np.max(np.abs(a - pin_constraint_dynamics(m4, q, v, tau))) < SOLVER
        tau_back, lam_back = inverse_dynamics(m4, q, v, a)
        assert np.max(np.abs(tau_back - tau[m4.loops.drive_v])) < 1e-10
        assert np.max(np.abs(lam_back - lam)) < 1e-10


def test_free_motion_conserves_energy(m4):
    """No torque, gravity ⊥ the plane: kinetic energy is constant (0.5 s, DOP853)."""
    q = m4.home
    v = passive_velocity(m4, q, np.array([5.0]))
    data = m4.model.createData()

    def rhs(_t, x):
        return np.r_[x[3:], forward_dynamics(m4, x[:3], x[3:], np.zeros(3))[0]]

    run = solve_ivp(rhs, (0.0, 0.5), np.r_[q, v], method="DOP853", rtol=1e-11, atol=1e-12)
    energy = np.array([0.5 * x[3:] @ pin.crba(m4.model, data, x[:3]) @ x[3:] for x in run.y.T])
    assert run.success and abs(run.y[0, -1] - q[0]) > 1.0  # the crank did move
    assert np.max(np.abs(energy / energy[0] - 1.0)) < SOLVER  # integrator rtol 1e-11
    assert max(np.linalg.norm(m4.closure_residual(x[:3])) for x in run.y.T) < EXACT


# -------------------------------------------------------------------------------- errors
def message(error, call, *args, **kwargs):
    """The message of the typed error that call(*args, **kwargs) raises."""
    with pytest.raises(error) as exc:
        call(*args, **kwargs)
    return str(exc.value)


def test_typed_errors(m4):
    lo, hi = fb.rocker_range(fb.geometry(m4))
    assert message(UnreachablePoseError, rcm_pin.inverse, m4, [0.5]) == (
        "four_bar: rocker angle 0.5 rad is outside the rocker's range (the crank circle and "
        f"the coupler circle about B do not meet); valid: rocker angles in [{lo:.6g}, {hi:.6g}] rad"
    )
    assert message(UnreachablePoseError, rcm_pin.forward, load("non_grashof"), [np.pi]) == (
        "four_bar: drives [3.141592653589793] admit no assembly (the loops cannot close); "
        "valid: drive values inside the workspace of four_bar"
    )
    assert message(InvalidInputError, rcm_pin.forward, m4, [0.1, 0.2]) == (
        "drives has shape (2,); valid: (1,) for four_bar (1 values)"
    )
    assert message(InvalidInputError, rcm_pin.inverse, m4, [1.0, 1.2]) == (
        "target has shape (2,); valid: (1,) values of rz of frame rocker"
    )


@pytest.mark.parametrize("arg", LINK_ARGS)
@pytest.mark.parametrize("value", [0, -0.02])
def test_error_non_positive_link_length(arg, value):
    what = {"frame": "l0 = |O1 O2|", "crank": "l1 = |O1 A| (driven)", "coupler": "l2 = |A B|"}
    what["rocker"] = "l3 = |O2 B| (output)"
    assert message(XacroArgumentError, rcm_pin.load, "four_bar", **{arg: value}) == (
        f"{arg}={value:g} is out of range for four_bar.urdf.xacro; valid: (0, 10] [m] ({what[arg]})"
    )
