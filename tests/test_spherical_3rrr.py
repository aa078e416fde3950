"""The spherical 3-RRR (paper 004, Fig. 5; the orthogonal Agile Eye): closed form vs Pinocchio.

Routes cross-checked: the family's closed form (rcm_pin/mechanisms/spherical_3rrr/), Pinocchio's
closures through the generic position / velocity code, the screw route, finite differences,
the paper's F1..F3 (F1 corrected) and constructions of the singular sets written here.
The issue's acceptance runs use 10^3 random orientations (N_ROT = 1000: about 40 s); the
default 100 keeps this module fast.
"""

from __future__ import annotations

import itertools

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, SOLVER
from scipy.optimize import brentq

import rcm_pin
from rcm_pin.analysis.closed_position import direct_position_multistart, direct_position_path
from rcm_pin.analysis.loop_velocity import (
    SINGULAR_TOL,
    classify,
    passive_velocity,
    velocity_matrices,
)
from rcm_pin.analysis.screws import screw_test
from rcm_pin.dynamics.constrained import forward_dynamics, inverse_dynamics, pin_constraint_dynamics
from rcm_pin.errors import (
    NotARotationError,
    SingularConfigurationError,
    UnreachablePoseError,
    XacroArgumentError,
)
from rcm_pin.mechanisms import spherical_3rrr as s3
from rcm_pin.mechanisms.spherical_3rrr import closed_form as sc
from rcm_pin.mechanisms.spherical_3rrr import paper
from rcm_pin.rotations import matrix_to_rpy, random_rotations, rot_x, rot_y, rpy_to_matrix

#: Random orientations per test (the acceptance count is 1000).
N_ROT = 100
#: A non-orthogonal design (link angles 70°/80°): type-2 poses off the type-1 set.
GENERAL = {f"theta_{i}{k}": t for i in (1, 2, 3) for k, t in ((1, 80), (2, 70))}


@pytest.fixture(scope="module")
def ms():
    return rcm_pin.load("spherical_3rrr")


@pytest.fixture(scope="module")
def mg():
    return rcm_pin.load("spherical_3rrr", **GENERAL)


def rot_err(m, value, R):
    return float(np.linalg.norm(m.output.error(np.asarray(value), np.asarray(R).reshape(9))))


def axes(m, q):
    """World axes (u_i, w_i, v_i) of every leg from Pinocchio (v_2, v_3: the tip frames' z)."""
    pin.framesForwardKinematics(m.model, m.data, m.q_pin(q))
    z = {n: m.data.oMi[m.model.getJointId(n)].rotation[:, 2] for n in ("u1", "u2", "u3", "w1",
         "w2", "w3", "v1")}  # fmt: skip
    for i in (2, 3):
        z[f"v{i}"] = m.data.oMf[m.frame_id(f"tip_{i}")].rotation[:, 2]
    return [(z[f"u{i}"], z[f"w{i}"], z[f"v{i}"]) for i in (1, 2, 3)]


def test_home_is_the_orthogonal_agile_eye(ms):
    q = ms.home
    assert np.all(q == 0.0) and np.linalg.norm(ms.closure_residual(q)) <= EXACT
    assert rot_err(ms, ms.output_value(q), np.eye(3)) <= EXACT
    e = np.eye(3)
    for i, (u, w, v) in enumerate(axes(ms, q)):  # (u_i, w_i0, v_i0) = (e_i, e_i+1, e_i+2)
        assert np.max(np.abs(np.array([u, w, v]) - e[[i, (i + 1) % 3, (i + 2) % 3]])) < EXACT
    assert (
        s3.geometry(ms).agile_eye
        and not s3.geometry(rcm_pin.load("spherical_3rrr", **GENERAL)).agile_eye
    )
    assert rcm_pin.mobility(ms, q).rank_mobility == 3
    # φ_i > 0 turns w_i about u_i by the right-hand rule (Pinocchio's axes, no closed form)
    turned = np.array([{"u1": 0.1, "u2": 0.2, "u3": 0.3}.get(j, 0.0) for j in ms.joint_names])
    (u1, w1, _), (u2, w2, _), (u3, w3, _) = axes(ms, turned)
    for u, w, w0, t in ((u1, w1, e[1], 0.1), (u2, w2, e[2], 0.2), (u3, w3, e[0], 0.3)):
        assert np.max(np.abs(w - pin.exp3(t * u) @ w0)) < EXACT


@pytest.mark.parametrize("name", ["default", "general"])
def test_inverse_then_forward_every_working_mode(name, ms, mg):
    """8 labelled working modes, residual ≤ 1e-12, the label is the sign of u_i·(w_i × v_i),
    the platform point at O stays at O, and the direct problem from the drives finds R."""
    m = ms if name == "default" else mg
    rng = np.random.default_rng(20)
    n_checked = 0
    for R in random_rotations(rng, N_ROT if name == "default" else N_ROT // 5):
        _, delta, _ = sc.leg_roots(s3.geometry(m), R)
        if np.any(delta < 0):  # the general design does not reach every orientation
            continue
        inv = rcm_pin.inverse(m, R)
        assert [s.mode for s in inv.solutions] == list(s3.MODES)
        for sol in inv.solutions:
            assert sol.residual <= EXACT and np.linalg.norm(m.closure_residual(sol.q)) <= EXACT
            assert rot_err(m, sol.output, R) < 1e-10
            signs = "".join("+" if u @ np.cross(w, v) > 0 else "-" for u, w, v in axes(m, sol.q))
            assert signs == sol.mode
            pin.framesForwardKinematics(m.model, m.data, m.q_pin(sol.q))
            assert np.linalg.norm(m.data.oMf[m.output.frame_id].translation) <= EXACT
            fwd = rcm_pin.forward(m, sol.q[m.loops.drive_q], all_modes=True)
            assert max(f.residual for f in fwd.solutions) <= EXACT
            assert min(rot_err(m, f.output, R) for f in fwd.solutions) < 1e-10
        n_checked += 1
    assert n_checked >= (N_ROT if name == "default" else 5)


def degenerate_orientations(g):
    """The four R with R v_i0 = ±u_i for every leg (built here: sign patterns, det = +1)."""
    out = []
    for signs in np.array(np.meshgrid(*[[1.0, -1.0]] * 3)).T.reshape(-1, 3):
        R = (signs[:, None] * g.u).T @ g.v0  # R v_i0 = s_i u_i (v0 orthonormal)
        if np.linalg.det(R) > 0:
            out.append(R)
    return out


def test_direct_problem_four_assembly_modes_map_back(ms):
    """Agile Eye: 4 assembly modes for every input (Bonev, Chablat and Wenger 2006), each
    one's orientation, through the inverse, gives back the drives in one working mode; the
    closed form's 8 real solutions add the 4 drive-independent orientations R v_i0 = ±u_i,
    which close the loops for any drives; the purely numeric multistart finds no other."""
    g = s3.geometry(ms)
    degenerate = degenerate_orientations(g)
    assert len(degenerate) == 4
    rng = np.random.default_rng(21)
    counts = []
    for k, phi in enumerate(rng.uniform(-np.pi, np.pi, (N_ROT, 3))):
        every = sc.direct_position(g, phi, degenerate=True)
        assert len(every) == 8
        extra = [R for R in every if min(np.max(np.abs(R - D)) for D in degenerate) < 1e-9]
        assert len(extra) == 4
        for R in degenerate:  # closed loops whatever the drives: all legs type 1
            q = s3.full_q(ms, R, phi)
            assert np.linalg.norm(ms.closure_residual(q)) <= EXACT and verdicts(ms, q)[0][0]
        fwd = rcm_pin.forward(ms, phi, all_modes=True)
        counts.append(fwd.count)
        for f in fwd.solutions:
            assert f.residual <= EXACT and np.linalg.norm(ms.closure_residual(f.q)) <= EXACT
            pin.framesForwardKinematics(ms.model, ms.data, ms.q_pin(f.q))
            assert np.linalg.norm(ms.data.oMf[ms.output.frame_id].translation) <= EXACT
            inv = rcm_pin.inverse(ms, f.output)
            back = [np.max(np.abs(np.angle(np.exp(1j * (s.q[ms.loops.drive_q] - phi)))))
                    for s in inv.solutions]  # fmt: skip
            assert min(back) < 1e-10
        if k < 3:
            numeric = direct_position_multistart(ms, phi, n_starts=48, seed=k)
            for s in numeric.solutions:
                R = s.output.reshape(3, 3)
                dist = [rot_err(ms, f.output, R) for f in fwd.solutions]
                dist += [rot_err(ms, D.reshape(9), R) for D in degenerate]
                assert min(dist) < SOLVER
    assert set(counts) == {4}


def test_direct_problem_general_design_polynomial_vs_multistart(mg):
    """General link angles: the degree-4 polynomial's assembly modes (2, 4, 6 or 8) equal
    the numeric multistart's and each maps back through the inverse."""
    g = s3.geometry(mg)
    rng = np.random.default_rng(26)
    counts, checked = set(), 0
    for R0 in random_rotations(rng, 40):
        if np.any(sc.leg_roots(g, R0)[1] < 0):
            continue
        phi = sc.inverse_position(g, R0)[rng.integers(8)]
        fwd = rcm_pin.forward(mg, phi, all_modes=True)
        assert min(rot_err(mg, f.output, R0) for f in fwd.solutions) < 1e-10
        counts.add(fwd.count)
        for f in fwd.solutions:
            assert f.residual <= EXACT
            back = [np.max(np.abs(np.angle(np.exp(1j * (s.q[mg.loops.drive_q] - phi)))))
                    for s in rcm_pin.inverse(mg, f.output).solutions]  # fmt: skip
            assert min(back) < 1e-10
        if checked < 3:
            numeric = direct_position_multistart(mg, phi, n_starts=64, seed=checked)
            assert numeric.count == fwd.count
        checked += 1
        if checked == 10:
            break
    assert checked == 10 and counts <= {2, 4, 6, 8}


def test_continuation_stays_on_one_assembly_mode(ms):
    """A drive path from home: every step closed to 1e-12, one closed-form assembly mode."""
    g = s3.geometry(ms)
    path = np.linspace(0.0, 1.0, 41)[:, None] * np.array([0.9, -0.6, 1.2])
    qs = direct_position_path(ms, path, ms.home)
    rs = [ms.output_value(q).reshape(3, 3) for q in qs]
    for q, phi, R in zip(qs, path, rs, strict=True):
        assert np.linalg.norm(ms.closure_residual(q)) <= EXACT
        assert min(np.max(np.abs(R - C)) for C in sc.direct_position(g, phi)) < SOLVER
    steps = [np.linalg.norm(pin.log3(b @ a.T)) for a, b in itertools.pairwise(rs)]
    assert max(steps) < 0.1


def test_paper_f1_misprint_and_f2_f3():
    """tan φ_i of working mode +++ against the paper's F1..F3: F2, F3 as printed and F1
    corrected hold to 1e-10; the printed F1 does not."""
    g = sc.GeometrySpherical.from_params(rcm_pin.load("spherical_3rrr").loops.params)
    rng = np.random.default_rng(22)
    worst_printed = 0.0
    for a, b, c in rng.uniform(-0.6, 0.6, (N_ROT, 3)):
        phi = sc.inverse_position(g, rpy_to_matrix(a, b, c))[0]
        tan = paper.tan_phi(a, b, c)
        assert np.max(np.abs(np.tan(phi) - tan["corrected"])) < 1e-10
        worst_printed = max(worst_printed, abs(np.tan(phi[0]) - tan["printed"][0]))
        gap = np.sin(c) * np.sin(b) * (np.cos(c) + np.cos(a)) / (np.cos(a) * np.cos(b))
        assert abs(tan["printed"][0] - tan["corrected"][0] - gap) < EXACT
    assert worst_printed > 0.1
    one_angle = paper.tan_phi(0.3, 0.0, 0.0)  # a rotation about x alone: both agree
    assert abs(one_angle["printed"][0] - one_angle["corrected"][0]) < EXACT


def verdicts(m, q):
    """(type 1, type 2) from the family's A, B, from Pinocchio and from the screws."""
    t1, t2 = sc.measures(s3.geometry(m), *s3.pose_and_drives(m, q))
    c, st = classify(m, q), screw_test(m, q)
    return (t1 < SINGULAR_TOL, t2 < SINGULAR_TOL), (c.type1, c.type2), (st.type1, st.type2)


@pytest.mark.parametrize("name", ["default", "general"])
def test_velocities_and_regular_verdicts_random_poses(name, ms, mg):
    """ω = −A⁻¹B φ̇ (family) = Pinocchio's output Jacobian to 1e-9 = finite differences to
    1e-6; the three routes call every random pose regular."""
    m = ms if name == "default" else mg
    g = s3.geometry(m)
    rng = np.random.default_rng(23)
    h = 1e-6
    for k, R in enumerate(random_rotations(rng, N_ROT // 4)):
        if np.any(sc.leg_roots(g, R)[1] < 0):
            continue
        for sol in rcm_pin.inverse(m, R).solutions[:: 3 if k % 2 else 5]:
            q = sol.q
            assert verdicts(m, q) == ((False, False),) * 3
            R_q, phi = s3.pose_and_drives(m, q)
            a_mat, b_mat = sc.ab_matrices(g, R_q, phi)
            j_cf = -np.linalg.solve(a_mat, b_mat)
            j_pin = velocity_matrices(m, q).output_jacobian()
            assert np.max(np.abs(j_pin - j_cf)) < SOLVER * max(1.0, np.max(np.abs(j_cf)))
            if name == "default":  # the third route: derivatives of the paper's F1..F3
                j_paper = paper.output_jacobian(np.array(matrix_to_rpy(R_q)), phi)
                assert np.max(np.abs(j_paper - j_cf)) < SOLVER * max(1.0, np.max(np.abs(j_cf)))
            if k < 4:
                for j in range(3):
                    dp = np.zeros(3)
                    dp[j] = h
                    plus, minus = (rcm_pin.forward(m, phi + s * dp, q_guess=q).solutions[0]
                                   for s in (1, -1))  # fmt: skip
                    rp, rm = plus.output.reshape(3, 3), minus.output.reshape(3, 3)
                    fd = pin.log3(rp @ rm.T) / (2 * h)
                    assert np.max(np.abs(fd - j_pin[:, j])) < 1e-6


def test_agile_eye_type2_only_on_type1(ms):
    """det A of the Agile Eye in platform axes is ±D/∏|u_i × v_i|, D a sum of squares that
    vanishes only where some v_i ∥ u_i (closed_form docstring): checked on random poses."""
    g = s3.geometry(ms)
    for R in random_rotations(np.random.default_rng(24), N_ROT):
        for phi in sc.inverse_position(g, R):
            a_mat, _ = sc.ab_matrices(g, R, phi)
            uv = np.prod(np.linalg.norm(np.cross(g.u, g.v0 @ R.T), axis=1))
            assert abs(abs(np.linalg.det(a_mat)) - sc.agile_eye_d(R) / uv) < EXACT
        d = R[0, 0] * R[1, 1] * R[2, 2] + R[0, 1] * R[1, 2] * R[2, 0]
        assert abs(d - sc.agile_eye_d(R)) < EXACT


def test_singular_sets_three_routes(ms, mg):
    """Type 1 on the Agile Eye (v_1 = u_1, every φ_1 closes leg 1) and type 2 off type 1 on
    the general design (a sign change of det A along a path in mode +++, by brentq)."""
    g = s3.geometry(ms)
    for t, phi1 in ((0.3, 0.4), (-1.2, 2.0), (2.5, -0.7)):
        R = rot_x(t) @ rot_y(np.pi / 2)  # R v_10 = R e_z = e_x = u_1
        roots, _, _ = sc.leg_roots(g, R)
        q = s3.full_q(ms, R, np.array([phi1, roots[1, 0], roots[2, 0]]))
        assert np.linalg.norm(ms.closure_residual(q)) <= EXACT
        fam, pin_v, screw_v = verdicts(ms, q)
        assert fam[0] and fam == pin_v == screw_v
    with pytest.raises(SingularConfigurationError):
        rcm_pin.inverse(ms, rot_y(np.pi / 2))
    gg = s3.geometry(mg)
    rng = np.random.default_rng(25)
    found = 0
    for axis in rng.normal(size=(40, 3)):
        axis /= np.linalg.norm(axis)

        def det_a(s, axis=axis):
            R = pin.exp3(s * axis)
            return np.linalg.det(sc.ab_matrices(gg, R, sc.inverse_position(gg, R)[0])[0])

        s_grid = np.linspace(0.0, 1.5, 61)
        reach = [np.all(sc.leg_roots(gg, pin.exp3(s * axis))[1] > 1e-6) for s in s_grid]
        dets = [det_a(s) if ok else np.nan for s, ok in zip(s_grid, reach, strict=True)]
        for k in range(60):
            if reach[k] and reach[k + 1] and dets[k] * dets[k + 1] < 0:
                s_star = brentq(det_a, s_grid[k], s_grid[k + 1], xtol=1e-15, rtol=1e-15)
                R = pin.exp3(s_star * axis)
                q = s3.full_q(mg, R, sc.inverse_position(gg, R)[0])
                assert np.linalg.norm(mg.closure_residual(q)) <= EXACT
                fam, pin_v, screw_v = verdicts(mg, q)
                assert fam == pin_v == screw_v == (False, True)
                found += 1
                break
        if found >= 3:
            break
    assert found >= 3


def test_rotation_input_and_not_a_rotation(ms):
    R = rpy_to_matrix(0.2, -0.3, 0.5)
    a = rcm_pin.inverse(ms, R)
    b = rcm_pin.inverse(ms, R.reshape(9))
    assert a.count == b.count == 8
    assert all(
        np.max(np.abs(x.q - y.q)) < EXACT for x, y in zip(a.solutions, b.solutions, strict=True)
    )
    with pytest.raises(NotARotationError):
        rcm_pin.inverse(ms, np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(NotARotationError):
        rcm_pin.inverse(ms, 2.0 * np.eye(3))


def test_typed_errors(ms, mg):
    R = np.array([0.8194539039, -0.0186789332, 0.5728406382, -0.5401095598, 0.3092533927,
                  0.7827157866, -0.1917732067, -0.9507962119, 0.2433302296])  # fmt: skip
    with pytest.raises(UnreachablePoseError) as exc:
        rcm_pin.inverse(mg, R)
    assert str(exc.value) == (
        "spherical_3rrr: orientation out of reach of leg 3 (the cone of w_i about u_i misses "
        "the cone about v_i, Δ < 0); valid: orientations with |γ_i − θ_i1| ≤ θ_i2 ≤ "
        "min(γ_i + θ_i1, 2π − γ_i − θ_i1), γ_i = angle(u_i, v_i)"
    )
    with pytest.raises(SingularConfigurationError) as exc:
        rcm_pin.inverse(ms, rot_y(np.pi / 2))  # R e_z = e_x: v_1 on u_1
    assert str(exc.value) == (
        "spherical_3rrr: the platform axis of leg 1 lies on its base axis, every drive angle "
        "closes the leg (type 1); valid: an orientation with v_i not along u_i"
    )


@pytest.mark.parametrize(
    "arg", ["proximal_radius", "distal_radius", "platform_radius", "m_platform", "m_pair"]
)
def test_error_non_positive_argument(arg):
    """The xacro's declared range (0, ...] rejects 0 (the wording is the range validator's)."""
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load("spherical_3rrr", **{arg: 0})
    assert f"{arg}=0" in str(exc.value) and "valid: (0, " in str(exc.value)


def test_kkt_dynamics_vs_pinocchio(ms):
    """The 6d closures' world rows (rx, ry, rz) are independent: the KKT forward dynamics
    equals pin.constraintDynamics and inverts through the inverse dynamics."""
    rng = np.random.default_rng(27)
    for R in random_rotations(rng, 4):
        for sol in rcm_pin.inverse(ms, R).solutions[::3]:
            q = sol.q
            v = passive_velocity(ms, q, rng.normal(size=3))
            tau = np.zeros(ms.nv)
            tau[ms.loops.drive_v] = 0.05 * rng.normal(size=3)  # [N·m]
            a, lam = forward_dynamics(ms, q, v, tau)
            assert np.max(np.abs(a - pin_constraint_dynamics(ms, q, v, tau))) < SOLVER
            tau_back, lam_back = inverse_dynamics(ms, q, v, a)
            assert np.max(np.abs(tau_back - tau[ms.loops.drive_v])) < 1e-10
            assert np.max(np.abs(lam_back - lam)) < 1e-10
