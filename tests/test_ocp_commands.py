"""The payloads behind ``rcm-pin ocp ik`` and ``rcm-pin ocp track`` (ocp.commands)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rcm_pin
from ocp.commands import format_ik, format_track, ik_command, track_command
from rcm_pin.cli._common import to_jsonable
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.mechanisms.rcm import closed_form


def test_ik_command_pose_and_position():
    q = np.array([0.3, -0.2, 0.09, 0.4, 0.5, 0.6])
    pose = closed_form.tool_pose(q)
    alpha, beta = np.arctan2(pose[2, 1], pose[2, 2]), -np.arcsin(pose[2, 0])
    gamma = np.arctan2(pose[1, 0], pose[0, 0])
    xyz = pose[:3, 3].tolist()
    out = ik_command("rcm_bevel", xyz, [alpha, beta, gamma])
    assert out["success"] and out["position_error"] < 1e-10 and out["orientation_error"] < 1e-10
    assert np.allclose(closed_form.tool_pose(out["q"]), pose, atol=1e-10)
    pos = ik_command("rcm_bevel", xyz)
    assert pos["mode"] == "position" and np.allclose(pos["q"][:3], q[:3], atol=1e-9)
    assert "q1 =" in format_ik(out) and json.dumps(to_jsonable(out))
    with pytest.raises(UnreachablePoseError):
        ik_command("rcm_bevel", [0.0, 0.0, 0.3])
    with pytest.raises(InvalidInputError):
        ik_command("rcm_bevel", [0.0, 0.1])


def test_track_command():
    out = track_command(n_intervals=20)
    assert out["success"] and out["tracking_error_m"] < 1e-9 and out["effort_limits"] is None
    assert "tracking error" in format_track(out) and json.dumps(to_jsonable(out))
    with pytest.raises(InvalidInputError):
        track_command(n_intervals=20, limit_scale=-1.0)


def test_ik_command_closed_mechanism_output():
    """planar_3rrr: --pose x, y, rz with the closures as constraints, checked by
    Pinocchio (closure residual) and by rcm_pin.inverse (one of its working modes)."""
    target = [0.01, 0.02, 0.1]
    out = ik_command("planar_3rrr", pose=target)
    assert out["success"] and out["mode"] == "output" and out["closure_residual"] < 1e-9
    assert np.allclose([out["output"][c] for c in ("x", "y", "rz")], target, atol=1e-9)
    mech = rcm_pin.load("planar_3rrr")
    modes = rcm_pin.inverse(mech, target).solutions
    d = [np.abs((np.array(out["q"]) - s.q + np.pi) % (2 * np.pi) - np.pi).max() for s in modes]
    assert min(d) < 1e-7
    assert "closure residual" in format_ik(out) and json.dumps(to_jsonable(out))
    with pytest.raises(InvalidInputError, match="closed mechanism: give pose"):
        ik_command("planar_3rrr", [0.01, 0.02, 0.0])
    with pytest.raises(InvalidInputError, match=r"\(3,\)"):
        ik_command("planar_3rrr", pose=[0.01, 0.02])
    with pytest.raises(InvalidInputError, match=r"\(serial\) is a 3x4 tool pose"):
        ik_command("rcm_bevel", pose=[0.01, 0.02, 0.1])


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_ik_command_catalogue_arms(name):
    mech = rcm_pin.load(name)
    home = mech.home
    pose = rcm_pin.tool_pose(mech, home)
    out = ik_command(name, pose[:3, 3] + [0.02, -0.01, 0.0])
    assert out["success"] and out["position_error"] < 1e-9 and len(out["q"]) == mech.nq
