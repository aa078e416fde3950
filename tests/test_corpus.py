"""Every URDF example-robot-data installs, loaded by path as a user would (no family, the
last link as the tool): each check agrees with a second route built from the URDF alone
(plain Pinocchio, :mod:`corpus`) or refuses with a typed error — never a traceback, never
a wrong pose. ``benchmarks/corpus.py`` adds the slow commands (workspace, view)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import corpus

ROBOTS = corpus.corpus()
#: Our own fixtures for what example-robot-data lacks (each also has its own test module):
#: continuous and continuous-mimic joints, a double parallelogram with a wrist, a robot
#: without inertias (the ROS workspace and the LAAS sidecars: test_packages, test_laas_*).
FIXTURES = [
    Path(__file__).parent / "data" / name
    for name in (
        "continuous_joints.urdf",
        "double_parallelogram_continuous.urdf",
        "rcm_wrist_arm.urdf",
        "no_inertia_arm.urdf",
    )
]

#: The robots rcm-pin refuses, each with the words its refusal must contain (the reason).
#: Every other robot must pass every check.
REFUSED = {
    # a mimic naming a joint the file does not have (index_q1 for Left_index_q1)
    "alex_description/alex_psyonic_hands": "mimics 'index_q1', which the URDF does not have",
    # mimic primaries on a later branch than their followers: Pinocchio cannot build them
    "romeo_description/romeo": "which Pinocchio meets after it",
    "talos_data/talos_full_v2": "which Pinocchio meets after it",
    "talos_data/talos_full_v2_box": "which Pinocchio meets after it",
    # rigid bodies: no joint a Mechanism has a coordinate for
    "iris_description/iris_simple": "no moving joint",
    "hector_description/quadrotor_base": "no moving joint",
    # a xacro macro file saved as .urdf: no robot in it
    "ur_description/ur3": "0 links (a macro file without a robot?)",
}


def test_the_corpus_is_installed():
    assert len(ROBOTS) >= 60, corpus.robots_dir()


@pytest.mark.parametrize("path", ROBOTS + FIXTURES, ids=corpus.robot_id)
@pytest.mark.parametrize("check", [corpus.check_fk, corpus.check_ik, corpus.check_cli_fk])
def test_corpus(path, check):
    outcome = corpus.run(check, path)
    assert outcome.status != "failed", outcome.detail
    reason = REFUSED.get(corpus.robot_id(path))
    if reason is None:
        assert outcome.status == "ok", outcome.detail
    else:
        assert outcome.status == "refused" and reason in outcome.detail, outcome.detail
