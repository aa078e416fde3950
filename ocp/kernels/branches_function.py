"""Every checked branch of a six- or four-DOF RCM pose as one ``casadi.Function``.

``rcm_branches(value, limits) -> (q, output, info)`` mirrors, for a pose value ``value``
(12,) = (x, y, z, R row by row) and ``limits`` (12,) = (lower, upper), the numpy route of
:func:`rcm_pin.inverse` on the rcm family (operation for operation, so the results agree
to rounding and the decisions are the same):

1. the eight analytic branches of :func:`rcm_pin.mechanisms.rcm.ik_scalar.ik_pose_one`
   (the same formulas in the same order, so the same bits: the angle variants a, −a,
   a + π, π − a by ``if_else``; the branch table
   :data:`rcm_pin.mechanisms.rcm.ik_tables._TABLE6`; its SO(3) screen); four-DOF: the two
   branches of the vectorised ``ik_pose_4dof`` (:func:`_principal4`; numpy's ``arctan2``
   ufunc may round an ulp away from the C library's, so q agree to 1e-12 there); in the
   near-aligned wrist band (SING_TOL < h < 1e-3, where the scalar IK hands the pose to
   the vectorised code) q6 from q4 ± q6 as the vectorised ``_wrist_near_aligned``
   (:func:`_near_aligned_q6`; q to 1e-12 there, the same decisions);
2. :meth:`~rcm_pin.mechanisms.rcm.ik_solutions.IKSolutions.fit_limits`: each angle as q,
   q + 2π or q − 2π where strictly closer to the box (the violation
   |x − min(max(x, lower), upper)|, tie to the earlier);
3. the check of :func:`rcm_pin.analysis.branch_check.check_branches`: the output frame's
   placement by the symbolic forward kinematics of :class:`ocp.symbolic.SymbolicModel`
   (Pinocchio's model, mimic joints included), the output value (x, y, z, R), the error
   [p − p_t; log₃(R R_tᵀ)] (:func:`ocp.closure.log3`), the residual max |e| and the limit
   flag lower − 1e-12 ≤ q ≤ upper + 1e-12.

Outputs (B = 8 branches, 2 four-DOF): ``q`` (B·n,) the fitted branches row by row,
``output`` (12 B,) their values row by row, ``info`` (B + 2,) = (residuals, limit
flags, b), the limit flags as one number (Σ 2^i over the branches i inside the limits,
exact in floating point), b > 0 where the numpy route
leaves this path (R farther from SO(3) than ``KEEP_TOL``, the test of
:func:`~rcm_pin.analysis.pose_target.plain_pose`, which ``inverse`` leaves to the kernel
and which covers the scalar IK's screen; the scalar IK declines: |p| ≤ POS_TOL,
ρ ≤ SING_TOL·|p|, the aligned wrist h ≤ SING_TOL; four-DOF: p off the tool z axis,
ρ ≤ SING_TOL; or a branch misses the target by more than ``BRANCH_TOL``, NaN included),
and the caller then runs that route.
"""

from __future__ import annotations

import hashlib
from typing import Any

import casadi as ca
import numpy as np

from ocp.closure import log3
from ocp.kernels.digest import source_digest, update_with_tree
from ocp.kernels.serial_rhs import _to_pin
from ocp.symbolic import SymbolicModel
from rcm_pin.analysis.branch_check import BRANCH_TOL, LIMIT_TOL
from rcm_pin.analysis.pose_target import KEEP_TOL
from rcm_pin.mechanisms.rcm.ik_tables import (
    _NEAR,
    _TABLE4,
    _TABLE6,
    AXIS_TOL,
    POS_TOL,
    SING_TOL,
)
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.so3_defect import so3_defect

PI = np.pi
#: Bump when the function's math changes (part of the structure key, with a digest of
#: the sources that write it: :func:`_sources`).
VERSION = "6"


def _variants(a: Any) -> list[Any]:
    """(a, −a, a + π, π − a) wrapped to (−π, π], as :func:`.ik_scalar._variants`."""
    return [
        a,
        ca.if_else(a < PI, -a, a),
        a + ca.if_else(a > 0.0, -PI, PI),
        ca.if_else(a >= 0.0, PI, -PI) - a,
    ]


def _kept(x: Any) -> Any:
    """``x`` ≥ 0 (or inf) as it is, in a node CasADi's simplifier does not see through:
    it would rewrite sqrt(s)² as s and y·(1/r) as y/r, which round differently from the
    scalar route's operations (fmax(x, 0) = x for every x ≥ 0)."""
    return ca.fmax(x, 0.0)


def _principal(c: list[Any], wrist: str) -> tuple[list[Any], Any]:
    """The 24 variants of :func:`.ik_scalar.ik_pose_one` (4 per coordinate) and the decline
    condition, from c = the 3×4 pose row by row."""
    x, y, z = c[3], c[7], c[11]
    rho = _kept(ca.sqrt(y * y + z * z))
    r = ca.sqrt(rho * rho + x * x)
    # the scalar route's 0.0 − y (+0.0 at y = ±0: q1 = +π, not −π, for z < 0), which
    # CasADi would simplify to −y
    a1, a2 = ca.atan2(ca.if_else(y == 0.0, 0.0, -y), z), ca.atan2(x, rho)
    ir, irho = _kept(1.0 / r), _kept(1.0 / rho)
    ex, ey, ez = x * ir, y * ir, z * ir
    c1, s1, c2 = z * irho, -y * irho, rho * ir
    s1s2, c1s2 = s1 * ex, c1 * ex
    j, k, m = (2, 0, 1) if wrist == "zyz" else (0, 2, 1)
    w2j = ex * c[j] + ey * c[4 + j] + ez * c[8 + j]
    w2k = ex * c[k] + ey * c[4 + k] + ez * c[8 + k]
    w2m = ex * c[m] + ey * c[4 + m] + ez * c[8 + m]
    w0j = c2 * c[j] + s1s2 * c[4 + j] - c1s2 * c[8 + j]
    w1j = c1 * c[4 + j] + s1 * c[8 + j]
    h = ca.sqrt(w0j * w0j + w1j * w1j)
    a4 = ca.atan2(w1j, w0j)
    if wrist == "zyz":
        a5, a6 = ca.atan2(h, w2j), ca.atan2(w2m, -w2k)
    else:
        a5, a6 = ca.atan2(-w2j, h), ca.atan2(w2m, w2k)
    a6 = ca.if_else(h < _NEAR, _near_aligned_q6(c, a1, a2, a4, wrist), a6)
    values = [*_variants(a1), *_variants(a2), r, -r, r, r]
    values += [*_variants(a4), *_variants(a5), *_variants(a6)]
    bad = ca.logic_or(ca.logic_or(r <= POS_TOL, rho <= SING_TOL * r), h <= SING_TOL)
    return values, ca.logic_or(bad, _off_screen(c))


def _near_aligned_q6(c: list[Any], a1: Any, a2: Any, a4: Any, wrist: str) -> Any:
    """q6 in the near-aligned wrist band (h < 1e-3) from the well-conditioned q4 ± q6:
    :func:`rcm_pin.mechanisms.rcm.analytic_ik._wrist_near_aligned` (R_w = (Rx(q1)
    Ry(q2))ᵀ R from cos and sin of the principal q1, q2, its entries summed in matmul's
    order; numpy's ufuncs may round an ulp away from the C library's, so q6 agrees to
    1e-12 there)."""
    cx, sx, cy, sy = ca.cos(a1), ca.sin(a1), ca.cos(a2), ca.sin(a2)
    m = [[cy, 0.0, sy], [sx * sy, cx, -sx * cy], [-cx * sy, sx, cx * cy]]  # Rx(q1) Ry(q2)

    def w(i: int, j: int) -> Any:  # R_w[i, j] = Σ_k m[k][i] R[k, j]
        return m[0][i] * c[j] + m[1][i] * c[4 + j] + m[2][i] * c[8 + j]

    if wrist == "zyz":
        plus = w(2, 2) >= 0.0  # near q5 = 0: q4 + q6 well determined, else q4 − q6
        s = ca.atan2(w(1, 0) - w(0, 1), w(0, 0) + w(1, 1))
        d = ca.atan2(-(w(1, 0) + w(0, 1)), w(1, 1) - w(0, 0))
    else:
        plus = w(2, 0) >= 0.0  # s5 = −Rw20 ≤ 0: q4 + q6 well determined
        s = ca.atan2(-(w(1, 2) + w(0, 1)), w(1, 1) - w(0, 2))
        d = ca.atan2(w(1, 2) - w(0, 1), w(1, 1) + w(0, 2))
    q6 = ca.if_else(plus, s - a4, a4 - d)
    return q6 - 2.0 * PI * ca.ceil((q6 - PI) / (2.0 * PI))  # wrap to (−π, π]


def _principal4(c: list[Any]) -> tuple[list[Any], Any]:
    """The 4-DOF twin of :func:`_principal`: the block of
    :func:`rcm_pin.mechanisms.rcm.analytic_ik.ik_pose_4dof` (its operations in its order;
    −ey, not 0 − ey, as there), declining where it raises or projects (p off the tool z
    axis by more than AXIS_TOL, ρ ≤ SING_TOL, R off the screen)."""
    ex, ey, ez = c[2], c[6], c[10]
    rho = _kept(ca.sqrt(ey * ey + ez * ez))
    a1, a2 = ca.atan2(-ey, ez), ca.atan2(ex, rho)
    q3 = c[3] * ex + c[7] * ey + c[11] * ez
    dx, dy, dz = c[3] - q3 * ex, c[7] - q3 * ey, c[11] - q3 * ez
    off = ca.sqrt(dx * dx + dy * dy + dz * dz)
    c1, s1 = ez / rho, -ey / rho
    w00 = rho * c[0] + s1 * ex * c[4] - c1 * ex * c[8]
    w10 = c1 * c[4] + s1 * c[8]
    a4 = ca.atan2(w10, w00)
    values = [*_variants(a1), *_variants(a2), q3, q3, q3, q3, *_variants(a4)]
    bad = ca.logic_or(ca.logic_or(off > AXIS_TOL, rho <= SING_TOL), _off_screen(c))
    return values, bad


def _off_screen(c: list[Any]) -> Any:
    """Whether :func:`rcm_pin.analysis.pose_target.plain_pose` would send R to the SVD
    projection (first-order distance from SO(3) above KEEP_TOL, or det R ≤ 0; the same
    arithmetic, so the same decision: ``inverse`` leaves that test to the kernel). It
    covers the scalar IK's screen (:func:`.ik_scalar._screen`, 1e-12), where the numpy
    route projects too."""
    sq, det = so3_defect([c[i] for i in (0, 1, 2, 4, 5, 6, 8, 9, 10)])
    return ca.logic_not(ca.logic_and(0.5 * ca.sqrt(sq) <= KEEP_TOL, det > 0.0))


def _fit(q: list[Any], lo: Any, up: Any) -> list[Any]:
    """fit_limits of one branch: q, q + 2π, q − 2π per angle (q3, index 2, a length)."""
    out = []
    for i, qi in enumerate(q):
        best, viol = qi, ca.fabs(qi - ca.fmin(ca.fmax(qi, lo[i]), up[i]))
        if i != 2:
            for shift in (2.0 * PI, -2.0 * PI):
                cand = qi + shift
                v = ca.fabs(cand - ca.fmin(ca.fmax(cand, lo[i]), up[i]))
                better = v < viol
                best, viol = ca.if_else(better, cand, best), ca.if_else(better, v, viol)
        out.append(best)
    return out


def supported(mech: Mechanism) -> bool:
    """A serial six- or four-DOF mechanism of the rcm family with a pose output (x, y, z,
    rotation), on the family's own position solver (a subclass may answer otherwise)."""
    from rcm_pin.analysis.capabilities import position_solver
    from rcm_pin.errors import UnknownMechanismError
    from rcm_pin.mechanisms.rcm import RcmPosition
    from rcm_pin.mechanisms.rcm.inverse import _check_rcm

    try:
        _check_rcm(mech)  # what the family's analytic IK accepts
    except UnknownMechanismError:
        return False
    return bool(
        mech.loops is None
        and mech.nq in (4, 6)
        and type(position_solver(mech)) is RcmPosition
        and mech.output.coords == ("x", "y", "z", "rotation")
    )


def build(mech: Mechanism, name: str) -> ca.Function:
    """The function ``name`` (module docstring), SX with CSE."""
    from rcm_pin.mechanisms.rcm.closed_form import wrist_type

    wrist = wrist_type(mech)
    assert supported(mech)
    n = mech.nq
    value, limits = ca.SX.sym("value", 12), ca.SX.sym("limits", 2 * n)
    lo, up = limits[:n], limits[n:]
    p_t, r_t = value[:3], ca.reshape(value[3:], 3, 3).T  # R_t row by row
    c = [value[3 + 3 * (i // 4) + i % 4] if i % 4 < 3 else value[i // 4] for i in range(12)]
    variants, bad = _principal4(c) if wrist is None else _principal(c, wrist)
    sm = SymbolicModel(mech.model)
    fk = sm.frame_placement(mech.output.frame_id)
    qs, outs, res, inside = [], [], [], 0.0
    for b, branch in enumerate(_TABLE4 if wrist is None else _TABLE6[wrist]):
        q = _fit([variants[4 * i + int(v)] for i, v in enumerate(branch)], lo, up)
        p, rot = fk(_to_pin(mech, ca.vertcat(*q), ca.SX.zeros(n))[0])
        e = ca.vertcat(p - p_t, log3(ca.mtimes(rot, r_t.T)))
        r_b = ca.mmax(ca.fabs(e))
        qs += q
        outs += [p[0], p[1], p[2], *(rot[i, j] for i in range(3) for j in range(3))]
        res.append(r_b)
        ok = [ca.logic_and(lo[i] - LIMIT_TOL <= q[i], up[i] + LIMIT_TOL >= q[i]) for i in range(n)]
        inside += ca.if_else(ca.logic_all(ca.vertcat(*ok)), 2.0**b, 0.0)  # bit b: inside
        bad = ca.logic_or(bad, ca.logic_not(r_b <= BRANCH_TOL))
    return ca.Function(
        name,
        [value, limits],
        [ca.vertcat(*qs), ca.vertcat(*outs), ca.vertcat(*res, inside, bad)],
        ["value", "limits"],
        ["q", "output", "info"],
        {"cse": True},
    )


def structure_key(mech: Mechanism) -> str:
    """What determines :func:`build`'s function: the kinematic tree as
    :class:`SymbolicModel` reads it, the coordinate map, the output frame, the wrist and
    the tolerances (the limits are an input)."""
    from rcm_pin.mechanisms.rcm.closed_form import wrist_type

    model = mech.model
    h = hashlib.sha256()
    update_with_tree(h, model)
    for idx in (mech.q_index, mech.continuous):
        h.update(np.asarray(idx, dtype=np.int64).tobytes() + b"|")
    tols = (POS_TOL, SING_TOL, AXIS_TOL, _NEAR, KEEP_TOL, LIMIT_TOL, BRANCH_TOL)
    h.update(f"{mech.output.frame_id}|{wrist_type(mech)}|{tols!r}|v={VERSION}".encode())
    h.update(_sources().encode())
    return h.hexdigest()


def _sources() -> str:
    """Digest of the modules whose code the function copies (a change rebuilds it)."""
    import ocp.closure
    import ocp.kinematics
    import ocp.symbolic
    import rcm_pin.mechanisms.rcm.analytic_ik
    import rcm_pin.mechanisms.rcm.ik_scalar
    import rcm_pin.mechanisms.rcm.ik_tables
    import rcm_pin.model.so3_defect

    mods = (ocp.closure, ocp.kinematics, ocp.symbolic, rcm_pin.mechanisms.rcm.analytic_ik,
            rcm_pin.mechanisms.rcm.ik_scalar, rcm_pin.mechanisms.rcm.ik_tables,
            rcm_pin.model.so3_defect)  # fmt: skip
    return source_digest(__file__, mods)


__all__ = ["VERSION", "build", "structure_key", "supported"]
