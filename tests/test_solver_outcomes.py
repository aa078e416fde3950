"""Honest solver outcomes (issue 11, item 3): a failed solve is a typed error, never a result.

* ``ocp track --limit-scale 0.01`` (IPOPT: Infeasible_Problem_Detected) raises
  :class:`SolverError` (exit status 3) naming the status and the worst limit violation; its
  ``result`` has ``success: false`` and the reason, no trajectories.
* ``ocp ik`` that does not converge, or ends outside the joint limits, is a
  :class:`SolverError` with such a ``result``; ``--pose`` takes a serial tool pose.
* ``simulate`` that leaves the joint range raises :class:`JointLimitError` (exit 2) naming
  the time and the joint; ``allow_outside_limits`` continues and records it.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp import paper000 as paper
from ocp.commands import _check_ik, ik_command, track_command
from ocp.ik import IKProblem
from ocp.ik_result import IKResult
from ocp.symbolic import SymbolicModel
from rcm_pin.cli import main
from rcm_pin.control.references import TRAJECTORIES
from rcm_pin.control.scenario import controller, run, scenarios
from rcm_pin.errors import InvalidInputError, JointLimitError, SolverError
from rcm_pin.mechanisms.rcm import closed_form
from rcm_pin.mechanisms.rcm.point import point_ik

# The infeasible tracking OCP (--limit-scale 0.01, --n 10). Its message is the project's
# wording with the solver's numbers in it: IPOPT's iteration count (screening solve
# included), its last primal infeasibility, and the worst violation at its last iterate,
# i.e. where IPOPT's restoration phase stopped (which force, at which collocation point).
# Those belong to IPOPT: they change with its version and with the rounding of every
# iterate, so they are wildcards here, checked against the result, the solver's own record
# and the solve's trajectories instead. The 0.0278 N limit is 1 % of the analytic peak q3
# force: a property of the problem, kept literally (and recomputed by a second route).
TRACK_REASON = (
    "paper 000 tracking OCP of rcm_bevel failed: ipopt Infeasible_Problem_Detected after "
    "{iterations} iterations (primal infeasibility {primal}); worst limit violation: q3 "
    "force {value} N against a 0.0278 N limit at t = {time} s"
)
TRACK_VALID = (
    "; valid: drive limits the reference can be tracked within (the analytic peak efforts: "
    "--limit-scale 1 and above, or no --limit-scale)"
)
TRACK_SCALE = 0.01
NUMBER = r"\d+(?:\.\d+)?(?:e[+-]\d+)?"  # a positive number as "{:.3g}" prints it


def _pattern(template: str) -> str:
    """``template`` as a regex: its text literal, each ``{name}`` a named number group."""
    parts = re.split(r"\{(\w+)\}", template)
    groups = {"iterations": r"\d+"}
    return "".join(
        re.escape(p) if i % 2 == 0 else f"(?P<{p}>{groups.get(p, NUMBER)})"
        for i, p in enumerate(parts)
    )


TRACK_REASON_RE = re.compile(_pattern(TRACK_REASON))
TRACK_MESSAGE_RE = re.compile(_pattern(TRACK_REASON) + re.escape(TRACK_VALID))
VALID = (
    "(the limits come from the xacro arguments, --arg KEY=VALUE), or allow_outside_limits=True "
    "(--allow-outside-limits) to continue and record it"
)
POSE = "--pose=1,0,0,0.02;0,1,0,-0.03;0,0,1,0.09"


def cli(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def peak_q123():
    """Paper 000's analytic peak efforts |tau| of q1..q3 by a second route (not
    ``paper.peak_efforts``): the reference through ``point_ik`` (positions only), velocities
    and accelerations by central differences (delta = 1e-4 s: 4e-8 relative), efforts by
    the CasADi twin's RNEA, on paper.peak_efforts' grid of 2001 times over one period."""
    mech = rcm_pin.load(paper.MECHANISM)
    t, delta = np.linspace(0.0, paper.HORIZON, 2001), 1e-4
    q = [
        np.array([point_ik(p) for p in paper.reference_position(t + s)]) for s in (-delta, 0, delta)
    ]
    v, a = (q[2] - q[0]) / (2 * delta), (q[2] - 2 * q[1] + q[0]) / delta**2

    def full(x: np.ndarray) -> np.ndarray:  # q4..q6 held at 0
        return np.array([mech.to_pin(np.concatenate([r, np.zeros(mech.nq - 3)])) for r in x])

    rnea = SymbolicModel(mech.model).rnea().map(len(t))
    tau = np.asarray(rnea(full(q[1]).T, full(v).T, full(a).T)).T
    return np.abs(np.array([mech.from_pin(x) for x in tau])).max(0)[:3]


def _check_infeasible_result(result: dict, peak: np.ndarray) -> None:
    """What the project promises of the infeasible solve's ``result``; the solver's numbers
    only as bounds and as consistency with the reason's text."""
    assert result["success"] is False and result["status"] == "Infeasible_Problem_Detected"
    reason = TRACK_REASON_RE.fullmatch(result["reason"])
    assert reason, result["reason"]
    worst = result["worst_violation"]
    assert reason.groupdict() == {
        "iterations": str(result["iterations"]),
        "primal": f"{result['primal_infeasibility']:.3g}",
        "value": f"{worst['value']:.3g}",
        "time": f"{worst['time_s']:.3g}",
    }
    assert result["iterations"] > 0
    # infeasible: more than IPOPT's default constr_viol_tol (1e-4), below which a point counts
    # as feasible
    assert result["primal_infeasibility"] > 1e-4
    assert (worst["coordinate"], worst["kind"]) == ("q3", "effort")
    limits = result["effort_limits"]
    np.testing.assert_allclose(limits[:3], TRACK_SCALE * peak, rtol=1e-6)  # 25x the FD error
    assert limits[3:] == [None, None, None] and worst["limit"] == limits[2]
    assert worst["value"] > worst["limit"]  # a violation, measured relative to its limit
    assert worst["ratio"] == pytest.approx(
        (worst["value"] - worst["limit"]) / worst["limit"], rel=1e-12
    )
    # at a collocation point of the grid: Radau IIA, 3 points per interval of h = T / N
    h = paper.HORIZON / result["n_intervals"]
    radau = np.array([(4 - np.sqrt(6)) / 10, (4 + np.sqrt(6)) / 10, 1.0])
    grid = h * (np.arange(result["n_intervals"])[:, None] + radau).ravel()
    assert np.abs(grid - worst["time_s"]).min() < 1e-12


# -- ocp track ------------------------------------------------------------------------------
def test_infeasible_track_exits_3_with_the_reason_and_no_trajectories(capsys, peak_q123):
    code, out, err = cli(capsys, "ocp", "track", "--limit-scale", "0.01", "--n", "10", "--json")
    error = json.loads(out)["error"]
    assert code == 3 and error["type"] == "SolverError"
    assert TRACK_MESSAGE_RE.fullmatch(error["message"]), error["message"]
    result = error["result"]
    assert error["message"] == result["reason"] + TRACK_VALID
    _check_infeasible_result(result, peak_q123)
    assert not {"q", "tau", "max_efforts", "tracking_error_m"} & set(result)


def test_infeasible_track_text_is_one_line_on_stderr(capsys):
    code, out, err = cli(capsys, "ocp", "track", "--limit-scale", "0.01", "--n", "10")
    assert code == 3 and out == "" and err.endswith("\n") and err.count("\n") == 1
    head = "rcm-pin: error: SolverError: "
    assert err.startswith(head) and TRACK_MESSAGE_RE.fullmatch(err[len(head) : -1]), err


def test_infeasible_track_api_raises_with_a_small_result(monkeypatch, peak_q123):
    """The reported numbers against the solver's own record and the solve's trajectories
    (``paper.solve`` watched): IPOPT's last primal infeasibility, the iterations of both
    solves, and the worst violation recomputed from the efforts, which Pinocchio's RNEA
    confirms from the positions, velocities and accelerations."""
    seen = {}
    solve = paper.solve

    def watched(ocp, mech, **kwargs):
        seen.update(ocp=ocp, mech=mech, res=solve(ocp, mech, **kwargs))
        return seen["res"]

    monkeypatch.setattr(paper, "solve", watched)
    with pytest.raises(SolverError) as info:
        track_command(n_intervals=10, limit_scale=TRACK_SCALE)
    assert TRACK_MESSAGE_RE.fullmatch(str(info.value)), str(info.value)
    result = info.value.result  # type: ignore[attr-defined]
    json.dumps(result, allow_nan=False)  # JSON-able as it is
    assert result["n_intervals"] == 10
    _check_infeasible_result(result, peak_q123)
    ocp, mech, res = seen["ocp"], seen["mech"], seen["res"]
    stats = ocp.limited_stats()
    screening = ocp._route().newton.solve(
        ocp._split(ocp.hold_guess(paper.initial_state(mech)))[1].ravel(),
        paper.initial_state(mech),
        ocp.stage_parameters(res.p_ref, np.zeros(mech.nq)),
        ocp.h,
    )  # the screening solve (Newton's method): the same iterations again
    assert result["primal_infeasibility"] == stats["iterations"]["inf_pr"][-1]
    assert result["iterations"] == res.iterations == stats["iter_count"] + screening.iterations
    # the worst violation, recomputed: the largest |tau| / limit of q1..q3 ...
    tau, limits = np.abs(mech.from_pin(res.tau))[:, :3], np.array(result["effort_limits"][:3])
    k, i = np.unravel_index(np.argmax(tau / limits), tau.shape)
    worst = result["worst_violation"]
    assert (mech.coordinate_names[i], tau[k, i], res.t_colloc[k]) == (
        worst["coordinate"], worst["value"], worst["time_s"]
    )  # fmt: skip
    # ... outweighs every position excess (the wrist locked at 0: range width 1e-3) ...
    lo, hi = (mech.from_pin(b) for b in paper.limits(mech, lock_wrist=True))
    q = mech.from_pin(res.q_colloc)
    position = np.maximum(lo - q, q - hi) / np.maximum(hi - lo, 1e-3)
    assert position.max() < worst["ratio"]
    # ... and the effort is the model's inverse dynamics at that collocation point
    data = mech.model.createData()
    rnea = pin.rnea(mech.model, data, res.q_colloc[k], res.v_colloc[k], res.a_colloc[k])
    assert abs(abs(mech.from_pin(rnea)[i]) - worst["value"]) <= 1e-9 * worst["value"]


def test_feasible_limited_track_is_a_result(capsys):
    code, out, _ = cli(capsys, "ocp", "track", "--limit-scale", "1", "--n", "10", "--json")
    payload = json.loads(out)
    assert code == 0 and payload["success"] and payload["status"] == "Solve_Succeeded"
    lim = np.array(payload["effort_limits"][:3])
    assert np.all(np.array(payload["max_efforts"][:3]) <= lim * (1 + 1e-6))


# -- ocp ik -----------------------------------------------------------------------------------
def test_ocp_ik_takes_a_serial_tool_pose(capsys):
    code, out, _ = cli(capsys, "ocp", "ik", "rcm_bevel", POSE, "--json")
    payload = json.loads(out)
    assert code == 0 and payload["success"] and payload["mode"] == "pose"
    T = closed_form.tool_pose(np.array(payload["q"]))
    np.testing.assert_allclose(T[:3, 3], [0.02, -0.03, 0.09], atol=1e-9)
    np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-9)


def test_ocp_ik_pose_api_matches_the_cli():
    T = np.array([[1, 0, 0, 0.02], [0, 1, 0, -0.03], [0, 0, 1, 0.09]], dtype=float)
    payload = ik_command("rcm_bevel", pose=T)
    np.testing.assert_allclose(closed_form.tool_pose(np.array(payload["q"]))[:3], T, atol=1e-9)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            [POSE, "--xyz", "0,0,0.1"],
            "--pose conflicts with --xyz / --rpy; valid: one of them",
        ),
        (
            [POSE, "--rpy", "0,0,0"],
            "--pose conflicts with --xyz / --rpy; valid: one of them",
        ),
        (
            ["--pose", "1,2,3"],
            "pose for rcm_bevel (serial) is a 3x4 tool pose [R | p] "
            "('r11,r12,r13,x;...;r31,r32,r33,z' on the CLI), got shape (3,)",
        ),
        (
            [],
            "rcm_bevel is a serial mechanism: give xyz (tool-centre position [m]) and "
            "optionally rpy, or pose (a 3x4 tool pose [R | p])",
        ),
    ],
)
def test_ocp_ik_pose_errors(capsys, argv, message):
    code, out, _ = cli(capsys, "ocp", "ik", "rcm_bevel", *argv, "--json")
    error = json.loads(out)["error"]
    assert code == 2 and error == {"type": "InvalidInputError", "message": message}


def test_ocp_ik_that_does_not_converge_exits_3(capsys):
    far = "--pose=1,0,0,0.02;0,1,0,-0.03;0,0,1,0.5"
    code, out, _ = cli(capsys, "ocp", "ik", "rcm_bevel", far, "--json")
    error = json.loads(out)["error"]
    assert code == 3 and error["type"] == "SolverError"
    assert error["message"].startswith("IK solver failed: IK of frame 'tool' (lm, max_iter, ")
    result = error["result"]
    assert result["success"] is False and result["status"] == "max_iter"
    assert result["reason"] == error["message"] and "q" not in result
    assert result["position_error"] > 0.3


def test_ocp_ik_outside_the_joint_limits_is_a_solver_error():
    """A converged solve whose configuration leaves the limits is no result."""
    mech = rcm_pin.load("rcm_bevel")
    prob = IKProblem(mech, mode="position")
    q = 0.5 * (mech.lower + mech.upper)
    q[2] = 0.2  # q3 upper limit: 0.12 m
    res = IKResult(mech.to_pin(q), True, "converged", "lm", 3, 0.0, 0.0, float("nan"), 0.0)
    with pytest.raises(SolverError) as info:
        _check_ik(mech, prob, res)
    assert str(info.value) == (
        "IK of rcm_bevel (lm, converged) ended outside the joint limits: q3 = 0.2 against its "
        "limit 0.12; valid: q3 in [0.05, 0.12]"
    )
    assert info.value.result == {  # type: ignore[attr-defined]
        "success": False,
        "reason": "IK of rcm_bevel (lm, converged) ended outside the joint limits: q3 = 0.2 "
        "against its limit 0.12",
        "mechanism": "rcm_bevel", "solver": "lm", "status": "converged", "iterations": 3,
        "residual": 0.0, "position_error": 0.0, "orientation_error": None,
        "constraint_violation": 0.0, "closure_residual": 0.0,
    }  # fmt: skip


# -- closed mechanisms: a result or a typed error, never a traceback ---------------------------
@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar"])
@pytest.mark.parametrize(
    "argv",
    [["accuracy"], ["ocp", "ik"], ["ocp", "track"], ["ocp", "ik", "--xyz", "0,0,0"]],
    ids=["accuracy", "ocp-ik", "ocp-track", "ocp-ik-xyz"],
)
def test_closed_mechanisms_give_a_result_or_a_typed_error(capsys, name, argv):
    args = [*argv[:2], name, *argv[2:]] if argv[0] == "ocp" else [argv[0], name]
    extra = ["--n", "5"] if argv[-1] == "track" else []
    code, out, _ = cli(capsys, *args, *extra, "--json")
    doc = json.loads(out)
    assert code in (0, 2, 3)
    if code:
        assert set(doc) == {"error"} and doc["error"]["type"].endswith("Error")
    if argv[-1] == "track":  # the tracking OCP needs a serial mechanism
        assert code == 2 and "loop closures" in doc["error"]["message"]


# -- simulate: the joint range -------------------------------------------------------------
def test_paper000_without_the_wider_q3_range_stops_naming_q3_and_the_time(capsys):
    code, out, _ = cli(capsys, "simulate", "rcm_bevel", "--duration", "0.2", "--json")
    assert code == 2
    assert json.loads(out)["error"] == {
        "type": "JointLimitError",
        "message": "rcm_bevel starts outside its joint range at t = 0 s: q3 = 0.221359 m "
        f"above its upper limit 0.12 m; valid: a run within [0.05, 0.12] m {VALID}",
    }


def test_paper000_with_q3_upper_completes_on_the_plant_and_the_controller(capsys):
    argv = ["simulate", "rcm_bevel", "--arg", "q3_upper=0.3", "--duration", "0.2", "--json"]
    code, out, _ = cli(capsys, *argv)
    (r,) = json.loads(out)["runs"]
    assert code == 0 and r["status"] == "completed" and r["outside_limits"] == []
    mech = rcm_pin.load("rcm_bevel", q3_upper="0.3")
    ctrl_model = controller(mech, scenarios(mech)["paper000"]).model
    assert mech.upper[2] == 0.3 and ctrl_model.upper[2] == 0.3


def test_allow_outside_limits_continues_and_records_it(capsys):
    argv = ["simulate", "rcm_bevel", "--duration", "0.2", "--allow-outside-limits"]
    code, out, _ = cli(capsys, *argv, "--json")
    (r,) = json.loads(out)["runs"]
    assert code == 0 and r["status"] == "completed"
    (o,) = r["outside_limits"]
    assert (o["joint"], o["side"], o["time_s"], o["limit"]) == ("q3", "upper", 0.0, 0.12)
    code, out, _ = cli(capsys, *argv)
    assert "  outside its range: q3 passes its upper limit 0.12 at t = 0 s" in out


def test_leaving_the_range_mid_run_names_the_crossing_time():
    """q3_lower = 0.18 m: the run stops where q3 passes it; the time agrees with the
    crossing interpolated from the samples of the same run continued with
    ``allow_outside_limits``."""
    mech = rcm_pin.load("rcm_bevel", q3_upper="0.3", q3_lower="0.18")
    with pytest.raises(JointLimitError) as info:
        run(mech, scenarios(mech)["paper000"])
    msg = str(info.value)
    head = "rcm_bevel leaves its joint range at t = "
    assert msg.startswith(head)
    t_stop = float(msg[len(head) :].split(" s:")[0])
    assert msg == (
        f"{head}{t_stop:.6g} s: q3 passes its lower limit 0.18 m; valid: a run within "
        f"[0.18, 0.3] m {VALID}"
    )
    res = run(mech, scenarios(mech)["paper000"], allow_outside_limits=True)
    (o,) = res.outside_limits
    k = int(np.argmax(res.q[:, 2] < 0.18))
    t0, t1, q0, q1 = res.t[k - 1], res.t[k], res.q[k - 1, 2], res.q[k, 2]
    t_cross = t0 + (0.18 - q0) / (q1 - q0) * (t1 - t0)
    assert abs(t_stop - t_cross) < 1e-5
    assert (o["joint"], o["side"], o["time_s"], o["limit"]) == ("q3", "lower", res.t[k], 0.18)
    assert o["farthest"] == pytest.approx(res.q[:, 2].min(), abs=1e-15)


def test_simulate_api_rejects_a_start_outside_the_range():
    from rcm_pin.control.computed_torque import ComputedTorque, Gains
    from rcm_pin.control.simulate import simulate

    mech = rcm_pin.load("rcm_bevel")
    ctrl = ComputedTorque(mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0))
    with pytest.raises(JointLimitError, match=r"^rcm_bevel starts outside its joint range"):
        simulate(mech, ctrl, 0.1)
    with pytest.raises(InvalidInputError):  # unchanged: bad durations first
        simulate(mech, ctrl, -1.0)
