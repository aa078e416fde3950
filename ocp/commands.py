"""What ``rcm-pin ocp ik`` and ``rcm-pin ocp track`` run: JSON-able payloads and text.

The CLI module (``rcm_pin.cli.ocp``) parses its arguments, calls :func:`ik_command` or
:func:`track_command` and prints the payload with ``--json`` or the ``format_*`` text.
Coordinates in payloads are the Mechanism coordinates (the papers' q1..qn).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

import rcm_pin
from ocp import paper000 as paper
from ocp.ik import IKProblem, Mode
from ocp.ik_result import IKResult, failure
from ocp.tracking import TrackingOCP, TrackingResult
from rcm_pin.errors import InvalidInputError, SolverError
from rcm_pin.model.output_choice import require_output
from rcm_pin.rotations import rpy_to_matrix


def ik_command(
    name: str | rcm_pin.Mechanism,
    xyz: ArrayLike | None = None,
    rpy: ArrayLike | None = None,
    *,
    pose: ArrayLike | None = None,
    q0: ArrayLike | None = None,
    solver: str = "auto",
    restarts: int = 10,
    xacro_args: dict[str, str] | None = None,
    trusted: bool = False,
) -> dict[str, Any]:
    """Numerical IK of any catalogue mechanism (or URDF path, or a loaded Mechanism: the
    CLI's, with its frame options).

    Serial: the tool frame, pose (``xyz`` and ``rpy`` = alpha, beta, gamma with
    R = Rz(gamma) Ry(beta) Rx(alpha)) or position only (``rpy`` None). Closed: ``pose``,
    the values of the output coordinates (``mech.output``, e.g. x, y, rz of the 3-RRR
    platform), with the loop closures as equality constraints; the closure residual is
    checked again by Pinocchio.

    Raises:
        InvalidInputError: the wrong target kind for the mechanism, or malformed values.
        UnreachablePoseError, SolverError: see :class:`ocp.ik.IKProblem`.
    """
    mech = (
        name
        if isinstance(name, rcm_pin.Mechanism)
        else rcm_pin.load(name, trusted=trusted, **(xacro_args or {}))
    )
    prob, target = _problem(mech, xyz, rpy, pose, restarts)
    start = None if q0 is None else mech.to_pin(mech.check_q(np.asarray(q0), "q0"))
    res = prob.solve(target, start, solver=solver, raise_on_failure=False)  # type: ignore[arg-type]
    _check_ik(mech, prob, res)
    out = {
        "mechanism": mech.name, "mode": prob.mode, "solver": res.solver, "status": res.status,
        "success": res.success, "iterations": res.iterations,
        "coordinates": list(mech.coordinate_names), "q": mech.from_pin(res.q),
        "residual": res.residual_norm, "position_error": res.position_error,
        "orientation_error": res.orientation_error,
    }  # fmt: skip
    if mech.loops is not None:
        out["output"] = mech.output.to_json(mech.output_value(res.q))
        out["target"] = mech.output.to_json(target)
        out["closure_residual"] = float(np.abs(mech.closure_residual(res.q)).max())
    return out


def _check_ik(mech: rcm_pin.Mechanism, prob: IKProblem, res: IKResult) -> None:
    """Raise the typed error of a failed solve or of a solution outside the joint limits
    (1e-9): :class:`UnreachablePoseError` at a stationary point with a residual,
    :class:`SolverError` otherwise; ``err.result`` is a small JSON-able dict (``success``
    False, ``reason``, the solver's status and statistics; no configuration)."""
    q = mech.from_pin(res.q)
    excess = np.maximum(mech.lower - q, q - mech.upper)
    err: Exception | None = None
    if not res.success:
        err = failure(res, prob.sm.frames[prob.fid].name, prob.reach_tol, mech.loops is not None)
    elif excess.max() > 1e-9:
        i = int(np.argmax(excess))
        bound = mech.upper[i] if q[i] > mech.upper[i] else mech.lower[i]
        err = SolverError(
            f"IK of {mech.name} ({res.solver}, {res.status}) ended outside the joint limits: "
            f"{mech.coordinate_names[i]} = {q[i]:.6g} against its limit {bound:.6g}; valid: "
            f"{mech.coordinate_names[i]} in [{mech.lower[i]:.6g}, {mech.upper[i]:.6g}]"
        )
    if err is None:
        return
    err.result = {  # type: ignore[attr-defined]
        "success": False, "reason": str(err).split("; valid:")[0], "mechanism": mech.name,
        "solver": res.solver, "status": res.status, "iterations": res.iterations,
        "residual": res.residual_norm, "position_error": res.position_error,
        "orientation_error": _finite([res.orientation_error])[0],
        "constraint_violation": res.constraint_violation,
        "closure_residual": res.closure_residual,
    }  # fmt: skip
    raise err


def _problem(
    mech: rcm_pin.Mechanism,
    xyz: ArrayLike | None,
    rpy: ArrayLike | None,
    pose: ArrayLike | None,
    restarts: int,
) -> tuple[IKProblem, np.ndarray]:
    """The IK problem and target of ``ik_command`` (serial: tool pose or position)."""
    if mech.loops is not None:
        coords = ", ".join(require_output(mech, "the CasADi IK").coords)
        if pose is None or xyz is not None or rpy is not None:
            raise InvalidInputError(
                f"{mech.name} is a closed mechanism: give pose = its output coordinates "
                f"({coords} of frame {mech.output.frame}); xyz / rpy are for serial ones"
            )
        prob = IKProblem(mech, restarts=restarts)
        return prob, prob.target_vector(np.asarray(pose, dtype=float))
    if pose is not None:
        if xyz is not None or rpy is not None:
            raise InvalidInputError("--pose conflicts with --xyz / --rpy; valid: one of them")
        T = np.asarray(pose, dtype=float)
        if T.shape not in {(3, 4), (4, 4)}:
            raise InvalidInputError(
                f"pose for {mech.name} (serial) is a 3x4 tool pose [R | p] "
                f"('r11,r12,r13,x;...;r31,r32,r33,z' on the CLI), got shape {T.shape}"
            )
        return IKProblem(mech, mode="pose", restarts=restarts), T
    if xyz is None:
        raise InvalidInputError(
            f"{mech.name} is a serial mechanism: give xyz (tool-centre position [m]) and "
            "optionally rpy, or pose (a 3x4 tool pose [R | p])"
        )
    p = np.asarray(xyz, dtype=float)
    if p.shape != (3,):
        raise InvalidInputError(f"xyz must be 3 numbers [m], got {xyz!r}")
    mode: Mode = "position" if rpy is None else "pose"
    target: np.ndarray = p
    if rpy is not None:
        target = np.eye(4)
        target[:3, :3], target[:3, 3] = rpy_to_matrix(*np.asarray(rpy, dtype=float)), p
    return IKProblem(mech, mode=mode, restarts=restarts), target


def format_ik(payload: dict[str, Any]) -> str:
    """Human-readable text of an :func:`ik_command` payload."""
    q = ", ".join(f"{n} = {v:.6g}" for n, v in zip(payload["coordinates"], payload["q"]))
    text = (
        f"{payload['mechanism']} IK ({payload['mode']}, {payload['solver']}, "
        f"{payload['status']}, {payload['iterations']} iterations)\n  {q}\n"
        f"  position error {payload['position_error']:.2e} m, orientation error "
        f"{payload['orientation_error']:.2e} rad"
    )
    if "closure_residual" in payload:
        text += f", closure residual {payload['closure_residual']:.2e} (Pinocchio)"
    return text


def track_command(
    name: str = paper.MECHANISM,
    *,
    n_intervals: int = 100,
    solver: str = "ipopt",
    limit_scale: float | None = None,
    jit: bool = False,
    compile: bool = False,
) -> dict[str, Any]:
    """Paper 000's tracking OCP; ``limit_scale`` puts the q1..q3 drive limits at that
    fraction of the analytic peak efforts (and locks the wrist), None: no drive limits;
    ``compile``: the stage functions compiled to C through the disk cache
    (:mod:`ocp.compiled`)."""
    limited = limit_scale is not None
    if limited and not 0.0 < float(limit_scale) <= 10.0:  # type: ignore[arg-type]
        raise InvalidInputError(f"limit_scale must lie in (0, 10], got {limit_scale!r}")
    ocp, mech = paper.build(
        name,
        n_intervals,
        solver=solver,
        drive_limits=limited,
        lock_wrist=limited,
        jit=jit,
        compile=compile,
    )
    peak = paper.peak_efforts(mech)
    lim = None
    if limited:
        lim = np.full(mech.nq, np.inf)
        lim[:3] = float(limit_scale) * peak[:3]  # type: ignore[arg-type]
    res = paper.solve(ocp, mech, effort_limits=lim, raise_on_failure=False)
    _check_track(mech, ocp, res, lim)
    exact = paper.exact_solution(mech, res.t_colloc)
    return {
        "mechanism": mech.name, "n_intervals": n_intervals, "solver": res.solver,
        "status": res.status, "success": res.success, "iterations": res.iterations,
        "solve_time_s": res.solve_time, "tracking_error_m": res.tracking_error,
        "tracking_rms_m": res.tracking_rms, "q3_upper_m": paper.Q3_UPPER,
        "peak_efforts": mech.from_pin(peak),
        "effort_limits": None if lim is None else mech.from_pin(lim),
        "max_efforts": mech.from_pin(np.abs(res.tau).max(0)),
        "effort_difference_to_exact": float(np.abs(res.tau - exact.tau).max()),
    }  # fmt: skip


def _worst_violation(
    mech: rcm_pin.Mechanism, ocp: TrackingOCP, res: TrackingResult, lim: np.ndarray | None
) -> dict[str, Any] | None:
    """The largest limit violation of a tracking solution (drive efforts at the
    collocation points against ``lim``, positions against the OCP's joint limits), by its
    excess relative to the limit (efforts) or to the joint range (positions, at least
    1e-3); None when every limit holds within 1e-6 of that scale (IPOPT relaxes bounds)."""
    worst: dict[str, Any] | None = None
    tau, q = np.abs(mech.from_pin(res.tau)), mech.from_pin(res.q_colloc)
    lo, hi = mech.from_pin(ocp.lower), mech.from_pin(ocp.upper)
    width = np.where(np.isfinite(hi - lo), np.maximum(hi - lo, 1e-3), np.inf)
    checks = [("position", np.maximum(lo - q, q - hi), width, q)]
    if lim is not None:
        lim_m = mech.from_pin(lim)
        checks.append(("effort", tau - lim_m, np.maximum(lim_m, 1e-12), tau))
    for kind, excess, scale, value in checks:
        ratio = np.where(np.isfinite(scale), excess / np.where(np.isfinite(scale), scale, 1), 0)
        k, i = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        if ratio[k, i] > 1e-6 and (worst is None or ratio[k, i] > worst["ratio"]):
            bound = lim_m[i] if kind == "effort" else (hi[i] if value[k, i] > hi[i] else lo[i])
            worst = {
                "coordinate": mech.coordinate_names[i], "kind": kind,
                "value": float(value[k, i]), "limit": float(bound),
                "time_s": float(res.t_colloc[k]), "ratio": float(ratio[k, i]),
            }  # fmt: skip
    return worst


def _describe(mech: rcm_pin.Mechanism, v: dict[str, Any]) -> str:
    """``"q3 force 365 N against a 0.028 N limit"`` (or a position against its bound)."""
    revolute = bool(mech.revolute[list(mech.coordinate_names).index(v["coordinate"])])
    if v["kind"] == "effort":
        what, unit = ("torque", "N m") if revolute else ("force", "N")
        value, limit = f"{v['value']:.3g} {unit}", f"{v['limit']:.3g} {unit}"
        return f"{v['coordinate']} {what} {value} against a {limit} limit"
    unit = "rad" if revolute else "m"
    return f"{v['coordinate']} = {v['value']:.4g} {unit} outside its limit {v['limit']:.4g} {unit}"


def _check_track(
    mech: rcm_pin.Mechanism, ocp: TrackingOCP, res: TrackingResult, lim: np.ndarray | None
) -> None:
    """Raise :class:`SolverError` for a failed or limit-violating solve (never a result).

    Its ``result`` is a small JSON-able dict: ``success`` False, ``reason``, the solver's
    status and statistics (IPOPT's last primal infeasibility) and the worst violation of the
    last iterate; no trajectories.
    """
    worst = _worst_violation(mech, ocp, res, lim)
    if res.success and worst is None:
        return
    inf_pr = ocp.limited_stats().get("iterations", {}).get("inf_pr", [])
    primal = float(inf_pr[-1]) if len(inf_pr) else None
    why = f"{res.solver} {res.status} after {res.iterations} iterations"
    if primal is not None:
        why += f" (primal infeasibility {primal:.3g})"
    if worst is not None:
        why += f"; worst limit violation: {_describe(mech, worst)} at t = {worst['time_s']:.3g} s"
    reason = f"paper 000 tracking OCP of {mech.name} failed: {why}"
    err = SolverError(
        f"{reason}; valid: drive limits the reference can be tracked within (the analytic "
        "peak efforts: --limit-scale 1 and above, or no --limit-scale)"
    )
    err.result = {  # type: ignore[attr-defined]
        "success": False, "reason": reason, "mechanism": mech.name, "solver": res.solver,
        "status": res.status, "iterations": res.iterations, "solve_time_s": res.solve_time,
        "n_intervals": ocp.N, "objective": res.objective, "primal_infeasibility": primal,
        "effort_limits": None if lim is None else _finite(mech.from_pin(lim).tolist()),
        "worst_violation": worst,
    }  # fmt: skip
    raise err


def _finite(values: list[float]) -> list[float | None]:
    """NaN and ±inf to None (strict JSON)."""
    return [float(v) if np.isfinite(v) else None for v in values]


def format_track(payload: dict[str, Any]) -> str:
    """Human-readable text of a :func:`track_command` payload."""
    lim = payload["effort_limits"]
    limits = "none" if lim is None else ", ".join(f"{v:.4g}" for v in lim[:3]) + " (q1..q3)"
    return (
        f"{payload['mechanism']}: paper 000 tracking OCP, N = {payload['n_intervals']}, "
        f"{payload['solver']} {payload['status']} in {payload['iterations']} iterations, "
        f"{1e3 * payload['solve_time_s']:.1f} ms\n"
        f"  q3 upper limit widened to {payload['q3_upper_m']} m; drive limits: {limits}\n"
        f"  tracking error max {payload['tracking_error_m']:.3e} m, rms "
        f"{payload['tracking_rms_m']:.3e} m; efforts differ from the exact solution by "
        f"{payload['effort_difference_to_exact']:.3e}"
    )


__all__ = ["format_ik", "format_track", "ik_command", "track_command"]
