"""The numeric inverse kinematics of a serial arm without a closed form says the truth: on a
redundant arm (example-robot-data baxter, 17 coordinates) it finds the poses its own
forward kinematics makes; "outside the workspace" only where the reach bound proves it,
otherwise "not found within N starts" (a solver failure, exit 3 in the CLI)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.reach import reach_bound
from rcm_pin.analysis.serial_ik import N_STARTS
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError, SolutionNotFoundError, UnreachablePoseError
from rcm_pin.mechanisms.arms import robots_dir

BAXTER = "baxter_description/urdf/baxter.urdf"
FIXTURE = Path(__file__).parent / "data" / "rcm_wrist_arm.urdf"
#: A solution of the numeric IK meets its target this well in forward kinematics.
SOLVED = 1e-9

#: A planar 2R arm (links 1.0 m and 0.3 m): the disc of radius 0.7 m about the base is
#: outside its workspace, inside its reach bound of 1.3 m.
TWO_R = """<robot name="two_r">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="1.0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="l2"/><child link="tip"/>
    <origin xyz="0.3 0 0"/></joint>
</robot>
"""


@pytest.fixture(scope="module")
def baxter():
    return rcm_pin.load(robots_dir() / BAXTER, tool_frame="left_gripper")


def test_every_reachable_baxter_pose_is_found(baxter):
    """20 poses from forward kinematics of seeded random in-limit configurations: each is
    solved (>= 19 promised, all found here), every solution meets its pose in FK."""
    rng = np.random.default_rng(2024)
    found = 0
    for _ in range(20):
        pose = rcm_pin.forward(baxter, rng.uniform(baxter.lower, baxter.upper)).solutions[0]
        result = rcm_pin.inverse(baxter, pose.output)
        found += 1
        for sol in result.solutions:
            assert sol.residual <= SOLVED and sol.within_limits
    assert found >= 19


def test_a_pose_beyond_the_reach_bound_is_proved_outside_the_workspace(baxter):
    bound = reach_bound(baxter, "left_gripper")
    with pytest.raises(UnreachablePoseError) as err:
        rcm_pin.inverse(baxter, [3.0, 0.0, 0.5], ("x", "y", "z"), starts=2)
    assert str(err.value) == (
        "baxter: target x=3, y=0, z=0.5 is outside the workspace: its position is 3.04138 m "
        f"from the base, beyond the reach of frame left_gripper ({bound:.6g} m: the link "
        f"offsets and prismatic travels along the chain); valid: a position within "
        f"{bound:.6g} m of the base"
    )


def test_the_reach_bound_holds_over_random_configurations(baxter):
    """The bound is an upper bound of |p| (the fixture has a prismatic insertion and mimic
    followers)."""
    arm = rcm_pin.load(FIXTURE, tool_frame="tool")
    rng = np.random.default_rng(7)
    for mech, frame in ((baxter, "left_gripper"), (arm, "tool")):
        bound = reach_bound(mech, frame)
        assert np.isfinite(bound)
        for _ in range(200):
            p = rcm_pin.forward(mech, rng.uniform(mech.lower, mech.upper)).solutions[0].output
            assert np.linalg.norm(p[:3]) <= bound


def test_not_found_is_not_called_outside_the_workspace():
    """The 2R arm's hole: within the reach bound, so "not found within N starts"."""
    arm = rcm_pin.from_urdf(TWO_R, "two_r", tool_frame="tip")
    with pytest.raises(SolutionNotFoundError) as err:
        rcm_pin.inverse(arm, [0.2, 0.0, 0.0], ("x", "y", "z"))
    assert str(err.value) == (
        f"two_r: no solution of target x=0.2, y=0, z=0 found within {N_STARTS} starts of the "
        "multistart least squares (seed 0); not proved unreachable (0.2 m from the base, "
        "within the reach bound 1.3 m); valid: more starts (inverse(..., starts=N), rcm-pin "
        "ik --starts N) or another target"
    )
    assert rcm_pin.inverse(arm, [1.2, 0.3, 0.0], ("x", "y", "z"), starts=3).count >= 1
    with pytest.raises(InvalidInputError, match=r"^starts 0 is not a count; valid: an "):
        rcm_pin.inverse(arm, [1.2, 0.3, 0.0], ("x", "y", "z"), starts=0)


def test_cli_ik_exit_statuses(tmp_path, capsys):
    path = tmp_path / "two_r.urdf"
    path.write_text(TWO_R)
    base = ["ik", str(path), "--tool-frame", "tip", "--json"]
    assert main([*base, "--xyz", "0.2,0,0", "--starts", "4"]) == 3
    doc = json.loads(capsys.readouterr().out)
    assert doc["error"]["type"] == "SolutionNotFoundError"
    assert "found within 4 starts" in doc["error"]["message"]
    assert main([*base, "--xyz", "2,0,0"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["type"] == "UnreachablePoseError"
    assert main([*base, "--xyz", "1.2,0.3,0", "--starts", "2"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["count"] >= 1 and doc["method"] == "multistart least squares"
