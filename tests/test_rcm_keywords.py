"""An RCM on a user's arm by keywords: ``load(path, tool_frame=, rcm_frame=,
rcm_axis_frame=, rcm_axis=)`` and the same options on the CLI; ``rcm-track`` on a file
(mechanical RCM and programmable RCM), never looking a path up in the catalogue.

The fixture ``data/rcm_wrist_arm.urdf`` is a double-parallelogram RCM arm (a crank and two
revolute <mimic> followers), an insertion slide, then a wrist (roll, pitch) and the tool
frame: its shaft frame ``shaft`` keeps the remote centre on its z axis for every q, its
tool frame does not once the wrist pitches."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.mechanisms.arms import robots_dir

FIXTURE = Path(__file__).parent / "data" / "rcm_wrist_arm.urdf"
#: The shaft line through the remote centre is an identity of the linkage: round-off only.
ROUND_OFF = 1e-12
#: The goals of the tracking runs: tip error of the solvers [m].
SOLVED = 1e-9
FRAMES = (
    "base_link, coupler_link, crank_link, holder_link, holder_to_shaft, insertion, pitch, "
    "pitch_follower_1, pitch_follower_2, rcm, rcm_joint, roll, roll_link, shaft, shaft_base, "
    "tool, tool_joint, universe, wrist_link, wrist_pitch, yaw, yaw_link"
)


def _random_q(mech, n, seed):
    return np.random.default_rng(seed).uniform(mech.lower, mech.upper, size=(n, mech.nq))


def test_the_shaft_frame_keeps_the_rcm_at_round_off():
    arm = rcm_pin.load(FIXTURE, tool_frame="tool", rcm_frame="rcm", rcm_axis_frame="shaft")
    assert arm.model.frames[arm.rcm.axis_frame_id].name == "shaft" and arm.rcm.axis == 2
    errors = [rcm_pin.rcm_error(arm, q) for q in _random_q(arm, 200, 0)]
    assert max(errors) <= ROUND_OFF
    # a second route: the no-mimic model, every joint set from the URDF's <mimic> tags
    full, data = arm.model_full, arm.model_full.createData()
    shaft, rcm = full.getFrameId("shaft"), full.getFrameId("rcm")
    for q in _random_q(arm, 50, 1):
        pin.framesForwardKinematics(full, data, arm.coupling.q_full(arm.to_pin(q)))
        d = data.oMf[rcm].translation - data.oMf[shaft].translation
        e = data.oMf[shaft].rotation[:, 2]
        assert np.linalg.norm(d - (d @ e) * e) <= ROUND_OFF
    same = rcm_pin.load(str(FIXTURE), tool_frame="tool", rcm_frame="rcm", rcm_axis_frame="shaft",
                        rcm_axis="z")  # fmt: skip
    assert same.rcm == arm.rcm
    bevel = rcm_pin.load("rcm_bevel", rcm_axis_frame="tool", rcm_axis="x")  # over <rcm_pin>
    assert bevel.model.frames[bevel.rcm.axis_frame_id].name == "tool" and bevel.rcm.axis == 0
    assert rcm_pin.load("rcm_bevel").rcm.axis_frame_id != bevel.rcm.axis_frame_id


def test_without_the_shaft_frame_the_wrist_shows_as_an_rcm_error():
    """The measured bug: the tool frame's z axis leaves the remote centre as the wrist
    pitches (centimetres to decimetres), although the linkage keeps the shaft through it."""
    arm = rcm_pin.load(FIXTURE, tool_frame="tool", rcm_frame="rcm")
    assert arm.model.frames[arm.rcm.axis_frame_id].name == "tool"
    errors = np.array([rcm_pin.rcm_error(arm, q) for q in _random_q(arm, 200, 0)])
    assert errors.max() > 0.05
    straight = _random_q(arm, 20, 1)
    straight[:, arm.joint_names.index("wrist_pitch")] = 0.0  # the wrist in line: no error
    assert max(rcm_pin.rcm_error(arm, q) for q in straight) <= ROUND_OFF


def test_bad_rcm_keywords_are_typed_with_exact_messages():
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.load(FIXTURE, tool_frame="tool", rcm_frame="rcm", rcm_axis="w")
    assert str(err.value) == (
        "rcm_axis 'w' is not an axis; valid: x, y or z (the shaft axis of the RCM axis frame)"
    )
    with pytest.raises(UnknownFrameError) as err:
        rcm_pin.load(FIXTURE, tool_frame="tool", rcm_frame="rcm", rcm_axis_frame="shaft_tip")
    assert str(err.value) == (
        f"unknown RCM axis frame 'shaft_tip' in rcm_wrist_arm; valid: {FRAMES}"
    )
    with pytest.raises(UnknownFrameError) as err:
        rcm_pin.load(FIXTURE, tool_frame="tool", rcm_frame="trocar")
    assert str(err.value) == f"unknown RCM frame 'trocar' in rcm_wrist_arm; valid: {FRAMES}"
    with pytest.raises(InvalidInputError) as err:
        rcm_pin.load(FIXTURE, tool_frame="tool", rcm_axis_frame="shaft")
    assert str(err.value) == (
        "rcm_wrist_arm: rcm_axis_frame is given but no RCM point (no rcm_frame argument, no "
        "<rcm_pin rcm_frame=...> element); valid: also rcm_frame=the frame at the remote "
        "centre, one of base_link, rcm, yaw_link, crank_link, coupler_link, holder_link, "
        "shaft_base, shaft, roll_link, wrist_link, tool"
    )


def _track(capsys, *argv):
    rc = main(["rcm-track", *argv, "--json"])
    return rc, json.loads(capsys.readouterr().out)


def test_rcm_track_on_a_file_with_a_mechanical_rcm(capsys):
    frames = ["--tool-frame", "tool", "--rcm-frame", "rcm", "--rcm-axis-frame", "shaft"]
    rc, doc = _track(capsys, str(FIXTURE), *frames, "--path", "spiral", "--duration", "0.05")
    assert rc == 0, doc
    assert doc["name"] == "rcm_wrist_arm" and doc["rcm"] == "mechanical"
    assert doc["tool_frame"] == "shaft" and doc["tip_frame"] == "tool"
    assert doc["trocar"] == [0.5, 0.0, 0.3]  # the rcm frame
    assert doc["rcm_error_max"] <= ROUND_OFF and doc["tip_error_max"] <= SOLVED
    q = np.asarray(doc["q"])
    assert q.shape == (51, 5) and np.abs(np.diff(q, axis=0)).max() < 1e-4  # continuation
    rc, doc = _track(capsys, str(FIXTURE), *frames[:4], "--path", "circle", "--duration", "0.05")
    assert rc == 0 and doc["tool_frame"] == "tool"  # the shaft measured on the tool frame
    assert doc["rcm_error_max"] > 1e-3


def test_rcm_track_on_an_arm_file_takes_the_qp_route(capsys, tmp_path):
    """A copy of panda under a name the catalogue does not have: loaded from the file with
    its --tool-frame, the trocar chosen for that mechanism (no look-up of the stem)."""
    path = tmp_path / "user_arm.urdf"
    shutil.copy(robots_dir() / "panda_description/urdf/panda.urdf", path)
    rc, doc = _track(
        capsys, str(path), "--tool-frame", "panda_hand_tcp", "--path", "circle", "--duration",
        "0.03",
    )  # fmt: skip
    assert rc == 0, doc
    assert doc["name"] == "user_arm" and doc["rcm"] == "programmable"
    assert doc["tool_frame"] == "panda_hand_tcp"
    assert doc["rcm_error_max"] <= 1e-6 and doc["tip_error_max"] <= 1e-4  # the QP's goals
    rc, doc = _track(capsys, str(path), "--path", "circle")
    assert rc == 2 and doc["error"]["type"] == "UnknownFrameError"
    assert doc["error"]["message"].startswith(
        "user_arm: the tool frame is not known (no tool_frame argument, no <rcm_pin "
        "tool_frame=...> element, no sidecar); valid: tool_frame=one of panda_link0, "
    )


def test_every_loading_command_takes_the_rcm_options(capsys):
    argv = ["fk", str(FIXTURE), "--tool-frame", "tool", "--rcm-frame", "rcm", "--json"]
    assert main([*argv, "--rcm-axis-frame", "shaft", "--rcm-axis", "z", "--q", "0,0,0,0,0"]) == 0
    assert json.loads(capsys.readouterr().out)["mechanism"] == "rcm_wrist_arm"
    ocp = ["ocp", "ik", str(FIXTURE), "--tool-frame", "tool", "--xyz", "0.5,0,0.2", "--json"]
    assert main(ocp) == 0  # the CasADi IK loads the path with its frame options too
    doc = json.loads(capsys.readouterr().out)
    assert doc["mechanism"] == "rcm_wrist_arm" and doc["position_error"] <= SOLVED
    assert main([*argv, "--rcm-axis", "w", "--q", "0,0,0,0,0"]) == 2
    assert json.loads(capsys.readouterr().out)["error"] == {
        "type": "InvalidInputError",
        "message": "rcm_axis 'w' is not an axis; valid: x, y or z (the shaft axis of the RCM "
        "axis frame)",
    }
    rc, doc = _track(
        capsys, str(FIXTURE), "--tool-frame", "tool", "--rcm-frame", "rcm", "--rcm-axis-frame",
        "nope", "--path", "arc",
    )  # fmt: skip
    assert rc == 2 and doc["error"] == {
        "type": "UnknownFrameError",
        "message": f"unknown RCM axis frame 'nope' in rcm_wrist_arm; valid: {FRAMES}",
    }


def test_the_shaft_axis_of_an_arm_is_checked_before_the_trocar_choice(capsys):
    rc, doc = _track(capsys, "panda", "--path", "circle", "--tool-axis", "x")
    assert rc == 2 and doc["error"] == {
        "type": "InvalidInputError",
        "message": "the trocar is chosen for the tool frame's z axis only; valid: give the "
        "trocar with another frame or axis",
    }
    rc, doc = _track(capsys, str(FIXTURE), "--tool-frame", "tool", "--rcm-frame", "rcm",
                     "--path", "arc", "--tool-axis", "x")  # fmt: skip
    assert rc == 2 and doc["error"]["message"] == (
        "rcm_wrist_arm has a mechanical RCM: its shaft is fixed by the mechanism; valid: omit "
        "the tool frame and axis (load with rcm_axis_frame= / rcm_axis=)"
    )


def test_the_fixture_has_a_positive_definite_mass_matrix():
    """Every moving link has an inertia: the mass matrix of the coordinates is regular."""
    from rcm_pin.dynamics.tree import mass_matrix

    arm = rcm_pin.load(FIXTURE, tool_frame="tool")
    for q in _random_q(arm, 5, 3):
        assert np.linalg.eigvalsh(mass_matrix(arm, q)).min() > 0.0
