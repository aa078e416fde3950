"""The command line: each subcommand's JSON output and its typed errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rcm_pin.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_list_json(capsys):
    code, out, _ = run(capsys, "list", "--json")
    names = [m["name"] for m in json.loads(out)["mechanisms"]]
    assert code == 0 and {"rcm_bevel", "rcm_bevel_4dof", "rcm_belt"} <= set(names)


def test_fk_json_matches_closed_form(capsys):
    from rcm_pin.mechanisms.rcm import closed_form

    q = [0.1, -0.2, 0.08, 0.3, 0.4, -0.5]
    code, out, _ = run(capsys, "fk", "rcm_bevel", "--q", ",".join(map(str, q)), "--json")
    payload = json.loads(out)
    (sol,) = payload["solutions"]
    assert code == 0 and payload["kind"] == "forward"
    np.testing.assert_allclose(sol["pose"], closed_form.tool_pose(np.array(q)), atol=1e-12)
    np.testing.assert_allclose(sol["output"]["rotation"], np.array(sol["pose"])[:3, :3], atol=0)
    assert sol["rcm_error"] < 1e-12
    assert list(sol["drives"]) == ["q1", "q2", "q3", "q4", "q5", "q6"]


def test_ik_json_prints_the_paper_example(capsys):
    pose = "0.75,-0.433,0.5,0;0.5,0.866,0,0;-0.433,0.25,0.866,0.01"
    code, out, _ = run(capsys, "ik", "rcm_bevel", "--arg", "q3_lower=-0.2", "--pose", pose,
                       "--json")  # fmt: skip
    payload = json.loads(out)
    branches = [s["q"] for s in payload["solutions"]]
    target = np.array([0, 0, 0.01, 0, 0.524, 0.524])
    assert code == 0 and payload["count"] == 8 and payload["position_only"] is False
    assert np.min(np.abs(np.array(branches) - target).max(axis=1)) < 5e-4
    assert 1e-5 < payload["rotation_projection_distance"] < 1e-4  # A_b is rounded


def test_ik_xyz_rpy(capsys):
    argv = ["ik", "rcm_bevel", "--xyz", "0.02,-0.03,0.09", "--rpy", "0.1,0.2,0.3"]
    code, out, _ = run(capsys, *argv, "--within-limits", "--json")
    payload = json.loads(out)
    assert code == 0 and payload["solutions"]
    assert all(s["within_limits"] for s in payload["solutions"])


def test_ik_position_only(capsys):
    code, out, _ = run(capsys, "ik", "rcm_bevel", "--xyz", "0.02,-0.03,0.09", "--json")
    payload = json.loads(out)
    assert code == 0 and payload["position_only"] and payload["count"] == 4
    for s in payload["solutions"]:
        np.testing.assert_allclose(np.array(s["pose"])[:3, 3], [0.02, -0.03, 0.09], atol=1e-12)


def test_urdf_check_and_render(capsys, tmp_path):
    assert run(capsys, "urdf", "--check")[0] == 0
    target = tmp_path / "x.urdf"
    code, _, _ = run(capsys, "urdf", "rcm_bevel", "--arg", "l9=0.25", "-o", str(target))
    assert code == 0 and "<robot" in target.read_text()


@pytest.mark.parametrize(
    ("argv", "kind", "message"),
    [
        (["fk", "nope", "--q", "0"], "UnknownMechanismError", "unknown mechanism 'nope'; valid:"),
        (["fk", "rcm_bevel", "--q", "0,1"], "InvalidInputError", "--q has 2 values; valid:"),
        (["fk", "rcm_bevel", "--q", "0,a"], "InvalidInputError", "is not a comma-separated list"),
        (["urdf", "rcm_bevel", "--arg", "l9"], "XacroArgumentError", "--arg 'l9' is not key=value"),
        (["ik", "rcm_bevel", "--pose", "1,0,0,0;0,1,0,0;0,0,1,0"], "SingularConfigurationError",
         "TOOL_AT_RCM"),
        (["ik", "rcm_bevel"], "InvalidInputError", "ik needs --pose, or --xyz"),
        (["ik", "rcm_bevel", "--pose", "1,0,0,0;0,1,0,0;0,0,1,0.1", "--xyz", "0,0,0.1"],
         "InvalidInputError", "--pose conflicts with --xyz / --rpy"),
        (["fk", "rcm_bevel", "--q", "0,0,0.1,0,0,0", "--all"], "InvalidInputError",
         "--all lists the assembly modes of closed mechanisms; rcm_bevel is serial"),
    ],
)  # fmt: skip
def test_errors_are_typed_json(capsys, argv, kind, message):
    code, out, _ = run(capsys, *argv, "--json")
    error = json.loads(out)["error"]
    assert code == 2 and error["type"] == kind and message in error["message"]


def test_error_without_json_goes_to_stderr(capsys):
    code, out, err = run(capsys, "fk", "nope", "--q", "0")
    assert code == 2 and out == "" and "UnknownMechanismError: unknown mechanism 'nope'" in err


def test_closed_mechanisms_are_listed(capsys):
    code, out, _ = run(capsys, "list", "--json")
    kinds = {m["name"]: m["kind"] for m in json.loads(out)["mechanisms"]}
    assert kinds["planar_3rrr"] == "closed" and kinds["five_bar"] == "closed"


@pytest.mark.parametrize(
    ("name", "pose"),
    [("planar_3rrr", "0.0,0.05,0.1"), ("five_bar", "0.03,0.25"), ("four_bar", "1.9")],
)
def test_closed_fk_all_modes_and_ik_round_trip(capsys, name, pose):
    target = np.array([float(v) for v in pose.split(",")])
    code, out, _ = run(capsys, "ik", name, "--pose", pose, "--json")
    inverse = json.loads(out)
    assert code == 0 and inverse["count"] >= 2
    drives = inverse["solutions"][0]["drives"]
    assert list(drives) == inverse["drive_names"]
    q_text = "--q=" + ",".join(map(str, drives.values()))  # "--q=": values may start with "-"
    code, out, _ = run(capsys, "fk", name, q_text, "--all", "--json")
    direct = json.loads(out)
    outputs = np.array([[s["output"][c] for c in direct["output_coords"]]
                        for s in direct["solutions"]])  # fmt: skip
    assert code == 0 and direct["count"] >= 2
    assert np.min(np.abs(outputs - target).max(axis=1)) < 1e-10
    assert max(s["residual"] for s in direct["solutions"]) < 1e-12


def test_closed_ik_needs_pose(capsys):
    code, out, _ = run(capsys, "ik", "planar_3rrr", "--xyz", "0,0,0", "--json")
    message = json.loads(out)["error"]["message"]
    assert code == 2 and message.startswith("closed mechanisms take --pose x,y,rz")


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_arms_fk_ik(capsys, name):
    import rcm_pin

    mech = rcm_pin.load(name)
    q = mech.home + 0.1
    code, out, _ = run(capsys, "fk", name, "--q", ",".join(map(str, q)), "--json")
    pose = np.array(json.loads(out)["solutions"][0]["pose"])
    text = ";".join(",".join(repr(float(v)) for v in row) for row in pose[:3])
    code, out, _ = run(capsys, "ik", name, "--pose", text, "--json")
    payload = json.loads(out)
    assert code == 0 and payload["count"] >= 1 and payload["method"] == "multistart least squares"
    for s in payload["solutions"]:
        np.testing.assert_allclose(s["pose"], pose, atol=1e-9)


def test_python_dash_m_runs_the_same_command_line():
    """``python -m rcm_pin`` is the ``rcm-pin`` entry point (the benchmarks call it)."""
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-m", "rcm_pin", "list", "--json"], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert "rcm_bevel" in [m["name"] for m in json.loads(done.stdout)["mechanisms"]]
    bad = subprocess.run([sys.executable, "-m", "rcm_pin", "fk", "nope"], capture_output=True)
    assert bad.returncode == 2
