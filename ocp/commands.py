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
from rcm_pin.errors import InvalidInputError
from rcm_pin.rotations import rpy_to_matrix


def ik_command(
    name: str,
    xyz: ArrayLike | None = None,
    rpy: ArrayLike | None = None,
    *,
    pose: ArrayLike | None = None,
    q0: ArrayLike | None = None,
    solver: str = "auto",
    restarts: int = 10,
    xacro_args: dict[str, str] | None = None,
) -> dict[str, Any]:
    """Numerical IK of any catalogue mechanism (or URDF path).

    Serial: the tool frame, pose (``xyz`` and ``rpy`` = alpha, beta, gamma with
    R = Rz(gamma) Ry(beta) Rx(alpha)) or position only (``rpy`` None). Closed: ``pose``,
    the values of the output coordinates (``mech.output``, e.g. x, y, rz of the 3-RRR
    platform), with the loop closures as equality constraints; the closure residual is
    checked again by Pinocchio.

    Raises:
        InvalidInputError: the wrong target kind for the mechanism, or malformed values.
        UnreachablePoseError, SolverError: see :class:`ocp.ik.IKProblem`.
    """
    mech = rcm_pin.load(name, **(xacro_args or {}))
    prob, target = _problem(mech, xyz, rpy, pose, restarts)
    start = None if q0 is None else mech.to_pin(mech.check_q(np.asarray(q0), "q0"))
    res = prob.solve(target, start, solver=solver)  # type: ignore[arg-type]
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


def _problem(
    mech: rcm_pin.Mechanism,
    xyz: ArrayLike | None,
    rpy: ArrayLike | None,
    pose: ArrayLike | None,
    restarts: int,
) -> tuple[IKProblem, np.ndarray]:
    """The IK problem and target of ``ik_command`` (serial: tool pose or position)."""
    if mech.loops is not None:
        coords = ", ".join(mech.output.coords)
        if pose is None or xyz is not None or rpy is not None:
            raise InvalidInputError(
                f"{mech.name} is a closed mechanism: give pose = its output coordinates "
                f"({coords} of frame {mech.output.frame}); xyz / rpy are for serial ones"
            )
        prob = IKProblem(mech, restarts=restarts)
        return prob, prob.target_vector(np.asarray(pose, dtype=float))
    if pose is not None or xyz is None:
        raise InvalidInputError(
            f"{mech.name} is a serial mechanism: give xyz (tool-centre position [m]) and "
            "optionally rpy; pose (output coordinates) is for closed mechanisms"
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
) -> dict[str, Any]:
    """Paper 000's tracking OCP; ``limit_scale`` puts the q1..q3 drive limits at that
    fraction of the analytic peak efforts (and locks the wrist), None: no drive limits."""
    limited = limit_scale is not None
    if limited and not 0.0 < float(limit_scale) <= 10.0:  # type: ignore[arg-type]
        raise InvalidInputError(f"limit_scale must lie in (0, 10], got {limit_scale!r}")
    ocp, mech = paper.build(
        name, n_intervals, solver=solver, drive_limits=limited, lock_wrist=limited, jit=jit
    )
    peak = paper.peak_efforts(mech)
    lim = None
    if limited:
        lim = np.full(mech.nq, np.inf)
        lim[:3] = float(limit_scale) * peak[:3]  # type: ignore[arg-type]
    res = paper.solve(ocp, mech, effort_limits=lim, raise_on_failure=False)
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
