"""``rcm-pin ocp ik | track``: JSON output against the analytic route, typed errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rcm_pin import closed_form
from rcm_pin.cli import main
from rcm_pin.rotations import rpy_to_matrix


def run(capsys, *argv):
    code = main(list(argv))
    return code, capsys.readouterr().out


def test_ocp_ik_reaches_the_pose(capsys):
    code, out = run(capsys, "ocp", "ik", "rcm_bevel", "--xyz", "0.02,-0.03,0.09",
                    "--rpy", "0.1,0.2,0.3", "--json")  # fmt: skip
    payload = json.loads(out)
    assert code == 0 and payload["success"]
    T = closed_form.tool_pose(np.array(payload["q"]))
    np.testing.assert_allclose(T[:3, 3], [0.02, -0.03, 0.09], atol=1e-9)
    np.testing.assert_allclose(T[:3, :3], rpy_to_matrix(0.1, 0.2, 0.3), atol=1e-9)


def test_ocp_track_recovers_the_analytic_tracking(capsys):
    code, out = run(capsys, "ocp", "track", "--n", "20", "--json")
    payload = json.loads(out)
    assert code == 0 and payload["success"]
    assert payload["tracking_error_m"] < 1e-6


@pytest.mark.parametrize(
    ("argv", "kind", "message"),
    [
        (["ocp", "ik", "rcm_bevel", "--xyz", "0,0"], "InvalidInputError", "--xyz has 2 values"),
        (
            ["ocp", "ik", "rcm_bevel", "--xyz", "0,0,0.5"],
            "UnreachablePoseError",
            "unreachable target: IK of frame 'tool'",
        ),
        (["ocp", "track", "--n", "1"], "InvalidInputError", "--n 1 is too small; valid:"),
    ],
)
def test_ocp_errors(capsys, argv, kind, message):
    code, out = run(capsys, *argv, "--json")
    error = json.loads(out)["error"]
    assert code == 2 and error["type"] == kind and message in error["message"]
