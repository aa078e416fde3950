"""The translational 3-PPaPa of paper 004 (Fig. 4): two parallelogram models vs the paper.

Routes cross-checked: the family's closed form (rcm_pin/mechanisms/translational_3ppapa.py:
the paper's explicit inverse, seeded Newton for the direct problem, the paper's A and
B = I), Pinocchio's closures of the crank + mimic model (square, full rank) and of the
4R-loop model (over-constrained, rank deficient) through the generic position, velocity,
screw and mobility code, and finite differences of the paper's F.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, SOLVER
from scipy.optimize import brentq

import rcm_pin
from rcm_pin.analysis.closed_position import direct_position_multistart, direct_position_path
from rcm_pin.analysis.loop_velocity import classify, velocity_matrices
from rcm_pin.analysis.screws import leg_twists, screw_test
from rcm_pin.analysis.singularity_model import singularity_model
from rcm_pin.errors import UnreachablePoseError, XacroArgumentError
from rcm_pin.mechanisms import translational_3ppapa as tp
from rcm_pin.mechanisms.translational_3ppapa import accuracy as acc
from rcm_pin.model.newton import constraint_rank

NAMES = ("translational_3ppapa", "translational_3ppapa_loops")


@pytest.fixture(scope="module")
def mm():
    return rcm_pin.load(NAMES[0])


@pytest.fixture(scope="module")
def ml():
    return rcm_pin.load(NAMES[1])


@pytest.fixture(scope="module")
def g(mm):
    return tp.geometry(mm)


def drives_of(m, q):
    return q[[m.joint_names.index(f"P{i}") for i in (1, 2, 3)]]


def rotation(m, q):
    pin.framesForwardKinematics(m.model, m.data, m.q_pin(q))
    return m.data.oMf[m.frame_id("platform")].rotation.copy()


def closure(m, q):
    return float(np.linalg.norm(m.closure_residual(q)))


def paper_ab(m, q):
    """The family's A, B (the paper's, normalised) at q."""
    ab = singularity_model(m).ab_matrices(m, q)
    assert ab.paper
    return ab.A, ab.B


def random_points(g, n, seed, margin=0.9):
    """n platform points in the reach box |p| < margin · min(l1, l2) (every mode reaches it)."""
    r = margin * min(g.l1, g.l2)
    return np.random.default_rng(seed).uniform(-r, r, (n, 3))


def diagonal_type2(g):
    """t with det A = 0 at x = y = z = t in mode ++/++/++: A is circulant, its eigenvalue
    along (1, 1, 1) is −1 + t/√(l2² − t²) + t/√(l1² − t²) (the complex pair vanishes only
    for l1 = l2)."""
    return brentq(
        lambda t: t / np.sqrt(g.l2**2 - t * t) + t / np.sqrt(g.l1**2 - t * t) - 1, 0, 0.999 * g.l2
    )


# ------------------------------------------------------------------------------ models
def test_both_models_load_with_their_closures(mm, ml):
    assert (mm.nq, mm.loops.n_rows, mm.loops.dof) == (9, 6, 3)  # square: 6 passive, 6 rows
    assert (ml.nq, ml.loops.n_rows, ml.loops.dof) == (21, 30, 3)  # 18 passive, 30 rows
    for m in (mm, ml):
        assert m.loops.drives == ("P1", "P2", "P3") and m.family is tp.FAMILY
        home = m.home
        assert closure(m, home) <= EXACT and np.max(np.abs(m.output_value(home))) <= EXACT
    assert mm.coupling.has_mimic and not ml.coupling.has_mimic


def test_mobility_rank_and_somov_malyshev(mm, ml):
    """Crank + mimic: n = 21 moving links (per leg a slider, per parallelogram two cranks
    and a coupler), 21 one-DOF pairs, 12 mimic couplings (class 1: q_k = −q_c, q_d = q_c)
    and two spherical cut pairs: W = 126 − 105 − 12 − 6 = 3, equal to the rank count.

    4R loops: the same 21 links and pairs, six spherical cut pairs (one per parallelogram)
    and two rigid ones (legs 2, 3 fixed to the platform): W = 126 − 105 − 18 − 12 = −9,
    while the rank count is 3: 12 of the 30 closure equations are redundant, namely
    6 = one per parallelogram (its four hinge axes are parallel, so the coincidence of the
    cut pin along the axes holds identically: a planar loop counted in space) and
    6 = the rotation rows of the two rigid platform closures (each leg's end already keeps
    the orientation of its base through its two parallelograms, like the platform)."""
    a, b = rcm_pin.mobility(mm), rcm_pin.mobility(ml)
    assert (a.n, a.pairs, a.W, a.rank_mobility, a.redundant) == (21, {5: 21, 1: 12, 3: 2}, 3, 3, 0)
    assert (b.n, b.pairs, b.W, b.rank_mobility, b.redundant) == (
        21,
        {5: 21, 1: 0, 3: 6, 6: 2},
        -9,
        3,
        12,
    )
    for p in random_points(tp.geometry(mm), 5, seed=1):
        for s in rcm_pin.inverse(ml, p).solutions[::13]:
            jac = ml.residual_and_jacobian(s.q)[1]
            assert jac.shape == (30, 21) and constraint_rank(jac) == 18
            assert rcm_pin.mobility(ml, s.q).rank_mobility == 3


# ------------------------------------------------------------------- position problems
def test_inverse_every_working_mode_then_forward(mm, g):
    """100 random points × 64 working modes (the acceptance run uses 10^3 points: set the
    count to 1000, ~50 s); Pinocchio's forward from a perturbed guess in a quarter of them."""
    rng, near = np.random.default_rng(2), 0
    for j, p in enumerate(random_points(g, 100, seed=3)):
        j %= 4  # forward from a guess in 16 of the 64 modes per point (all over 4 points)
        inv = rcm_pin.inverse(mm, p)
        assert tuple(s.mode for s in inv.solutions) == tp.MODES
        closed = tp.inverse_position(g, p)
        for k, (sol, (label, q, angles)) in enumerate(zip(inv.solutions, closed, strict=True)):
            assert sol.mode == label and closure(mm, sol.q) <= EXACT
            assert np.max(np.abs(sol.output - p)) < 1e-10
            assert np.max(np.abs(drives_of(mm, sol.q) - q)) < 1e-10
            assert np.max(np.abs(tp.platform_point(g, q, angles) - p)) < EXACT
            signs = np.array(tp.SIGN_PATTERNS[tp.MODES.index(label)], dtype=float)
            assert np.max(np.abs(tp.residual(g, q, p, signs))) < EXACT
            if k % 4 != j or abs(np.linalg.det(tp.a_from_angles(angles))) < 0.05:
                near += k % 4 == j  # near a type-2 set another assembly mode is close
                continue
            guess = sol.q + 1e-4 * rng.normal(size=mm.nq)
            fwd = rcm_pin.forward(mm, q, q_guess=guess).solutions[0]
            assert np.max(np.abs(fwd.output - p)) < 1e-10 and closure(mm, fwd.q) <= EXACT
    assert near < 100  # of 1600


def test_direct_problem_finds_every_mode_of_the_inverse(mm, g):
    """The family's seeded Newton finds P again in its working mode (4 modes × 12 points),
    and every assembly mode of three drive sets closes in Pinocchio."""
    rng = np.random.default_rng(4)
    for p in random_points(g, 12, seed=5):
        closed = tp.inverse_position(g, p)
        for k in rng.choice(64, 4, replace=False):
            label, q, _ = closed[k]
            found = tp.direct_position(g, q, modes=(label,))
            assert min(np.max(np.abs(x - p)) for _, x in found) < 1e-10
    for p in random_points(g, 3, seed=6):
        q = tp.inverse_position(g, p)[0][1]
        res = rcm_pin.forward(mm, q, all_modes=True)
        assert res.count >= 1 and min(np.max(np.abs(s.output - p)) for s in res.solutions) < 1e-10
        for s in res.solutions:
            assert (
                closure(mm, s.q) <= EXACT and np.max(np.abs(rotation(mm, s.q) - np.eye(3))) <= EXACT
            )
            assert np.max(np.abs(drives_of(mm, s.q) - q)) < 1e-10


def test_two_models_same_platform_motion_and_no_rotation(mm, ml, g):
    """Same drives (20 random points, 8 random modes each): from the family's configuration
    both models close to 1e-12 with the same platform point to 1e-12; from a perturbed guess
    (1e-4) Newton stops at a closure residual < 1e-13 m, so the points agree to 1e-10 (regular
    modes). Every assembly mode of two drive sets: the same points to 1e-12. The platform
    orientation is the identity to 1e-12 throughout."""
    rng = np.random.default_rng(7)
    for p in random_points(g, 20, seed=8):
        closed = tp.inverse_position(g, p)
        for k in rng.choice(64, 8, replace=False):
            _, q, angles = closed[k]
            regular = bool(abs(np.linalg.det(tp.a_from_angles(angles))) > 0.05)
            exact, guessed = [], []
            for m in (mm, ml):
                seed = tp.mech_q(m, q, angles)
                guesses = [seed] + [seed + 1e-4 * rng.normal(size=m.nq)] * regular
                for guess, out in zip(guesses, (exact, guessed), strict=False):
                    s = rcm_pin.forward(m, q, q_guess=guess).solutions[0]
                    assert closure(m, s.q) <= EXACT
                    assert np.max(np.abs(rotation(m, s.q) - np.eye(3))) <= EXACT
                    out.append(s.output)
            assert np.max(np.abs(exact[0] - exact[1])) <= EXACT
            assert np.max(np.abs(exact[0] - p)) <= EXACT
            if regular:
                assert np.max(np.abs(guessed[0] - guessed[1])) < 1e-10
    for p in random_points(g, 2, seed=10):
        q = tp.inverse_position(g, p)[0][1]
        a, b = (rcm_pin.forward(m, q, all_modes=True).solutions for m in (mm, ml))
        assert len(a) == len(b) >= 1
        for sa, sb in zip(a, b, strict=True):
            assert np.max(np.abs(sa.output - sb.output)) <= EXACT
            for m, s in ((mm, sa), (ml, sb)):
                assert closure(m, s.q) <= EXACT
                assert np.max(np.abs(rotation(m, s.q) - np.eye(3))) <= EXACT


# --------------------------------------------------------------- velocity, singularities
def test_paper_a_b_against_pinocchio_and_finite_differences(mm, ml, g):
    """J_out = −A⁻¹B with the paper's A and B = I equals Pinocchio's; B = ∂F/∂q = I exactly
    (F is linear in q); A = ∂F/∂p by central differences (h = 1e-6 m, error ~ h²)."""
    h = 1e-6
    for p in random_points(g, 6, seed=9, margin=0.8):
        for m in (mm, ml):
            for s in rcm_pin.inverse(m, p).solutions[::7]:
                a_mat, b_mat = paper_ab(m, s.q)
                assert np.array_equal(b_mat, np.eye(3))
                signs = np.array(tp.SIGN_PATTERNS[tp.MODES.index(s.mode)], dtype=float)
                assert np.max(np.abs(a_mat - tp.a_matrix(g, p, signs))) < 1e-10
                q = drives_of(m, s.q)
                fd_q = [
                    tp.residual(g, q + h * e, p, signs) - tp.residual(g, q, p, signs)
                    for e in np.eye(3)
                ]
                assert np.max(np.abs(np.array(fd_q).T / h - np.eye(3))) < 1e-9
                fd_p = [
                    tp.residual(g, q, p + h * e, signs) - tp.residual(g, q, p - h * e, signs)
                    for e in np.eye(3)
                ]
                assert np.max(np.abs(np.array(fd_p).T / (2 * h) - a_mat)) < 1e-6
                jac = velocity_matrices(m, s.q).output_jacobian()
                assert np.max(np.abs(jac + np.linalg.solve(a_mat, b_mat))) < SOLVER
                st = screw_test(m, s.q)
                assert classify(m, s.q).label == "regular" and not (st.type1 or st.type2)


@pytest.mark.parametrize("name", NAMES)
def test_type2_on_the_diagonal_and_type1_when_a_parallelogram_stretches(name):
    """det A = 0 at x = y = z = t* (t* = 0.1979 m for the defaults, inside the reach): type 2
    for A, Pinocchio and the screws. A parallelogram stretched (crank normal to its drive,
    |b| = l2: the reach boundary) is type 1 for Pinocchio's B and the screws, while the
    paper's A gets an infinite entry (tan 90°) and its B = I stays regular: that set is
    the one "not revealed by A and B" (multiplying row i by cos θ_i cos φ_i reveals it as
    a rank loss of B)."""
    m = rcm_pin.load(name)
    g = tp.geometry(m)
    t = diagonal_type2(g)
    assert abs(t - 0.19785212) < 1e-6
    s = rcm_pin.inverse(m, np.full(3, t)).solutions[0]
    a_mat, _ = paper_ab(m, s.q)
    assert s.mode == "++/++/++" and closure(m, s.q) <= EXACT and abs(np.linalg.det(a_mat)) < 1e-10
    assert classify(m, s.q).label == "type 2" and screw_test(m, s.q).type2
    stretched = np.array([0.05, 0.02, g.l2])  # leg 2: b = z = l2, its crank 2 along z
    for s in rcm_pin.inverse(m, stretched).solutions[:4]:
        a_mat, b_mat = paper_ab(m, s.q)
        assert closure(m, s.q) <= EXACT and np.max(np.abs(a_mat)) > 1e12
        assert np.array_equal(b_mat, np.eye(3))
        assert classify(m, s.q).label == "type 1" and screw_test(m, s.q).type1


# -------------------------------------------------------------------------------- errors
def test_typed_errors(mm):
    with pytest.raises(UnreachablePoseError) as exc:
        rcm_pin.inverse(mm, [0.0, 0.45, 0.0])
    assert str(exc.value) == (
        "translational_3ppapa: platform point [0.0, 0.45, 0.0] m is out of reach (a crank "
        "cannot span it); valid: |x|, |y|, |z| <= min(l1, l2) = 0.4 m"
    )
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load(NAMES[1], side_1=0)
    assert str(exc.value) == (
        "side_1=0 is out of range for translational_3ppapa.urdf.xacro; valid: (0, 10] [m] "
        "(l1: crank length of parallelogram 1)"
    )


def test_the_paper_control_reference_is_regular(mm, g):
    """The reference t (0.1, 0.12, 0.15) m, |t| <= 1 (paper 004, control), about P = 0 in mode
    ++/++/++: |det A| in [0.70, 1], σ_min/σ_max(A) > 0.3, drives in [0.82, 1.13] m (the
    dimensions documented in the xacro), regular for Pinocchio."""
    amp = np.array([0.1, 0.12, 0.15])
    dets, ratios, drives = [], [], []
    for t in np.linspace(-1.0, 1.0, 41):
        label, q, angles = tp.inverse_position(g, t * amp)[0]
        a_mat = tp.a_from_angles(angles)
        sv = np.linalg.svd(a_mat, compute_uv=False)
        dets.append(abs(np.linalg.det(a_mat)))
        ratios.append(sv[-1] / sv[0])
        drives.append(q)
        if t in (-1.0, 0.0, 1.0):
            assert label == "++/++/++"
            assert classify(mm, tp.mech_q(mm, q, angles)).label == "regular"
    assert min(dets) > 0.70 and max(dets) <= 1.0 + EXACT and min(ratios) > 0.3
    assert np.min(drives) > 0.82 and np.max(drives) < 1.13


def test_continuation_along_the_reference_both_models(mm, ml, g):
    """Drives of the reference (one period, 201 steps) by continuation from home: both models
    follow it, closed to 1e-12, on the reference to 1e-10, with each other to 1e-12."""
    amp = np.array([0.1, 0.12, 0.15])
    ref = np.sin(np.linspace(0.0, 2 * np.pi, 201))[:, None] * amp
    path = np.array([tp.inverse_position(g, p)[0][1] for p in ref])
    outs = []
    for m in (mm, ml):
        qs = direct_position_path(m, path, m.home)
        assert max(closure(m, q) for q in qs) <= EXACT
        outs.append(np.array([m.output_value(q) for q in qs]))
        assert np.max(np.abs(outs[-1] - ref)) < 1e-10
        assert max(np.max(np.abs(rotation(m, q) - np.eye(3))) for q in qs[::20]) <= EXACT
    assert np.max(np.abs(outs[0] - outs[1])) <= EXACT


def test_screw_form_restored(mm, g):
    """Paper 004's screw form V·r_i = V_i1 (r_ix + r_iy + r_iz) (r_i: the leg's wrench, the
    force normal to both crank translations; V_i1: the slider speed) is misprinted: the
    right-hand side is V_i1 (r_i·e_i), the power of the drive alone. Checked with Pinocchio's
    twists of the crank + mimic legs (pure translations) and its velocity V = J_out q̇."""
    rng, printed = np.random.default_rng(11), []
    for p in random_points(g, 10, seed=12, margin=0.8):
        for s in rcm_pin.inverse(mm, p).solutions[::9]:
            qd = rng.normal(size=3)
            v = velocity_matrices(mm, s.q).output_jacobian() @ qd
            for i, (twists, _) in enumerate(leg_twists(mm, s.q)):
                assert np.max(np.abs(twists[3:, 1:3])) == 0.0  # the cranks translate the leg
                r = np.cross(twists[:3, 1], twists[:3, 2])
                assert abs(r @ v - qd[i] * r[i]) < 1e-12 * np.linalg.norm(r) * (1 + abs(qd[i]))
                printed.append(abs(r @ v - qd[i] * r.sum()))
    assert max(printed) > 1e-2


def test_generic_multistart_finds_no_other_assembly_mode(mm, g):
    """The generic route (300 random starts on Pinocchio's closures) finds the same assembly
    modes as the family's seeded Newton (2 and 16 for these drives: a second route)."""
    for p, k, count in ((np.array([0.1, -0.2, 0.05]), 0, 2), (np.array([-0.1, 0.2, 0.15]), 21, 16)):
        q = tp.inverse_position(g, p)[k][1]
        family = tp.direct_position(g, q)
        numeric = direct_position_multistart(mm, q, n_starts=300, seed=1)
        assert len(family) == numeric.count == count
        for s in numeric.solutions:
            assert closure(mm, s.q) <= EXACT
            assert min(np.max(np.abs(s.output - x)) for _, x in family) < 1e-10


def test_accuracy_linear_cramer_vs_nonlinear_and_pinocchio(g):
    """1 mm errors in l1, l2, l3 (all legs), drives locked, at the reference's end point
    (0.1, 0.12, 0.15) m in mode ++/++/++: Cramer's rule (denominator det A) equals the linear
    solve; ∂F/∂l by finite differences; the nonlinear change equals Pinocchio's re-solve on
    the perturbed xacro to 1e-10 m; linear vs nonlinear differ by < 2 % (δp ≈ 2.5 mm here:
    the point is on the way to the type-2 set of the diagonal)."""
    p = np.array([0.1, 0.12, 0.15])
    label, q, angles = tp.inverse_position(g, p)[0]
    signs = np.array(tp.SIGN_PATTERNS[0], dtype=float)
    a_mat, dfdl = tp.a_matrix(g, p, signs), acc.length_jacobian(angles)
    h = 1e-7
    for j, key in enumerate(("l1", "l2", "l3")):
        gp = replace(g, **{key: getattr(g, key) + h})
        fd = (tp.residual(gp, q, p, signs) - tp.residual(g, q, p, signs)) / h
        assert np.max(np.abs(fd - dfdl[:, j])) < 1e-6
    rhs = np.array([1e-3, -2e-3, 0.5e-3])
    assert np.max(np.abs(acc.linear_error(a_mat, rhs) - np.linalg.solve(a_mat, rhs))) < EXACT
    rows = acc.accuracy_table(g, q, p, signs, angles, size=1e-3)
    args = {"l1": "side_1", "l2": "side_2", "l3": "offset"}
    for row in rows:
        assert 0.0 < row["relative"] < 0.02  # 1.4 %, 1.7 %, 1.6 % here (0.2 % at P = 0)
        dl = 1e-3 * np.array([row["length"] == k for k in ("l1", "l2", "l3")], dtype=float)
        value = getattr(g, str(row["length"])) + 1e-3
        m = rcm_pin.load(NAMES[0], **{args[str(row["length"])]: value})
        s = rcm_pin.forward(m, q, q_guess=tp.mech_q(m, q, angles)).solutions[0]
        assert closure(m, s.q) <= EXACT
        assert np.max(np.abs((s.output - p) - row["nonlinear"])) < 1e-10
        assert np.max(np.abs(acc.nonlinear_error(g, q, p, signs, dl) - row["nonlinear"])) == 0.0
    assert label == "++/++/++"


def test_error_unknown_parallelogram_model():
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load(NAMES[0], model="antiparallelogram")
    assert str(exc.value) == (
        "model='antiparallelogram' is not valid for translational_3ppapa.urdf.xacro; "
        "valid: one of mimic, loops"
    )
