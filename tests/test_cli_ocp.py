"""``rcm-pin ocp ik | track``: JSON output against the analytic route, typed errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.mechanisms.rcm import closed_form
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


@pytest.mark.parametrize("name", rcm_pin.names())
def test_ocp_ik_works_for_every_catalogue_entry(capsys, name):
    """Serial: --xyz of the tool centre at the home configuration (position mode); closed:
    --pose with the output coordinates there. The answer is checked by Pinocchio."""
    mech = rcm_pin.load(name)
    home = mech.home
    if mech.loops is None:
        xyz = rcm_pin.tool_pose(mech, home)[:3, 3]
        argv = ["--xyz=" + ",".join(f"{v:.12g}" for v in xyz)]  # "=": values may be < 0
    else:
        value = mech.output_value(mech.to_pin(home))
        argv = ["--pose=" + ",".join(f"{v:.12g}" for v in value)]
    code, out = run(capsys, "ocp", "ik", name, *argv, "--json")
    payload = json.loads(out)
    assert code == 0 and payload["success"], payload
    q = mech.to_pin(np.array(payload["q"]))
    if mech.loops is None:
        assert payload["mode"] == "position"
        np.testing.assert_allclose(rcm_pin.tool_pose(mech, payload["q"])[:3, 3], xyz, atol=1e-9)
    else:
        assert payload["mode"] == "output" and np.abs(mech.closure_residual(q)).max() < 1e-9
        err = mech.output.error(mech.output_value(q), value)
        assert np.abs(err).max() < 1e-8


def test_ocp_ik_closed_text(capsys):
    code, out = run(capsys, "ocp", "ik", "planar_3rrr", "--pose", "0.01,0.02,0.1")
    assert code == 0 and "planar_3rrr IK (output" in out and "closure residual" in out


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
        (["ocp", "ik", "rcm_bevel"], "InvalidInputError", "serial mechanism: give xyz"),
        (
            ["ocp", "ik", "five_bar", "--xyz", "0,0.2,0"],
            "InvalidInputError",
            "closed mechanism: give pose",
        ),
        (["ocp", "ik", "five_bar", "--pose", "0.1"], "InvalidInputError", "valid: (2,)"),
        (["ocp", "track", "four_bar", "--n", "5"], "InvalidInputError", "loop closures"),
    ],
)
def test_ocp_errors(capsys, argv, kind, message):
    code, out = run(capsys, *argv, "--json")
    error = json.loads(out)["error"]
    assert code == 2 and error["type"] == kind and message in error["message"]


def test_track_compile_with_fatrop_is_refused_before_any_build(capsys):
    """``--compile`` reaches the OCP's option check (fatrop differentiates the expanded NLP
    itself, so it cannot take compiled stage derivatives)."""
    code = main(["ocp", "track", "--compile", "--solver", "fatrop", "--n", "10", "--json"])
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and error["type"] == "InvalidInputError"
    assert error["message"] == (
        "hessian='exact', compile=True with solver='fatrop', jit=False; valid: hessian "
        "'exact' | 'cost', compile and 'cost' with solver 'ipopt' only (fatrop "
        "differentiates the expanded NLP itself), compile without jit (it replaces it)"
    )


@pytest.mark.parametrize("n", ["100000000", "23861"])
def test_track_beyond_the_memory_bound_is_refused_before_any_build(capsys, n):
    """The bound is the estimated memory (1 GiB at 1.5 kB per decision variable): 23 860
    intervals of paper 000's 30 variables; 1e8 would need 4.5 TB (std::bad_alloc)."""
    code = main(["ocp", "track", "--n", n, "--json"])
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and error["type"] == "InvalidInputError"
    assert error["message"].startswith(f"n_intervals {n} needs about ")
    assert error["message"].endswith(
        "GB of memory (45 kB per interval of 30 variables); valid: 1 to 23860 intervals (1 GiB)"
    )


def test_tracking_ocp_api_has_the_same_bound():
    from ocp.tracking import TrackingOCP
    from rcm_pin.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match=r"^n_intervals 100000000 needs about 4.5e\+03 GB"):
        TrackingOCP(rcm_pin.load("rcm_bevel"), horizon=1.0, n_intervals=10**8)
