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

#: The robots rcm-pin refuses, each with the words its refusal must contain (the reason).
#: Every other robot must pass every check.
REFUSED = {
    # Pinocchio's mimic parser needs a mimicked joint above its follower in the tree
    "alex_description/alex_psyonic_hands": "Pinocchio cannot parse the URDF",
    "romeo_description/romeo": "Pinocchio cannot parse the URDF",
    "talos_data/talos_full_v2": "Pinocchio cannot parse the URDF",
    "talos_data/talos_full_v2_box": "Pinocchio cannot parse the URDF",
}


def test_the_corpus_is_installed():
    assert len(ROBOTS) >= 60, corpus.robots_dir()


@pytest.mark.parametrize("path", ROBOTS, ids=corpus.robot_id)
@pytest.mark.parametrize("check", [corpus.check_fk, corpus.check_ik, corpus.check_cli_fk])
def test_corpus(path, check):
    outcome = corpus.run(check, path)
    assert outcome.status != "failed", outcome.detail
    reason = REFUSED.get(corpus.robot_id(path))
    if reason is None:
        assert outcome.status == "ok", outcome.detail
    else:
        assert outcome.status == "refused" and reason in outcome.detail, outcome.detail
