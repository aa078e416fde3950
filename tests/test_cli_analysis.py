"""``rcm-pin singularities | workspace | accuracy``: JSON output and typed errors."""

from __future__ import annotations

import json

import pytest

from rcm_pin.analysis.workspace import workspace_model
from rcm_pin.cli import main


def _json(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_singularities_q(capsys):
    code, out = _json(
        capsys, ["singularities", "rcm_bevel", "--q", "0.3,1.5707963267948966,0,0,0,0"]
    )
    (mode,) = out["modes"]
    assert code == 0 and mode["verdict"] == "singular"
    assert mode["full"]["rank"] == 3 and mode["position"]["rank"] == 1
    assert [c["name"] for c in mode["causes"]] == [
        "tool_centre_at_A",
        "output_axis_along_base_axis",
        "wrist_axes_aligned",
    ]


def test_singularities_grid_png(capsys, tmp_path):
    png = tmp_path / "g.png"
    code, out = _json(
        capsys, ["singularities", "rcm_bevel_4dof", "--grid", "2,3,5", "--wide", "--plot", str(png)]
    )
    assert code == 0 and len(out["values"]) == 5 and png.stat().st_size > 1000
    assert out["min"] < 1e-12  # q3 = 0 and cos q2 = 0 are on the wide grid


def test_singularities_pose_every_branch(capsys):
    pose = "0.75,-0.433,0.5,0;0.5,0.866,0,0;-0.433,0.25,0.866,0.01"  # paper 000's A_b
    code, out = _json(capsys, ["singularities", "rcm_bevel", "--arg", "q3_lower=-0.2", "--pose",
                               pose])  # fmt: skip
    assert code == 0 and len(out["modes"]) == 8
    assert {m["verdict"] for m in out["modes"]} == {"regular"}


def test_workspace_and_accuracy(capsys, tmp_path):
    code, out = _json(capsys, ["workspace", "rcm_bevel", "--samples", "5000"])
    assert code == 0 and out["spec"]["contains"] is True
    code, out = _json(capsys, ["accuracy", "rcm_belt"])
    assert code == 0 and out["rows"][0]["rcm_per_error"] > 0


@pytest.mark.parametrize("name", ["panda", "ur5", "four_bar", "planar_3rrr"])
def test_every_analysis_runs_on_arms_and_loops(capsys, tmp_path, name):
    """One path per subcommand: arms and closed mechanisms go through the same commands."""
    import numpy as np

    import rcm_pin

    mech = rcm_pin.load(name)
    home = mech.home
    inputs = home if mech.loops is None else home[mech.loops.drive_q]
    q = "--q=" + ",".join(repr(float(v)) for v in inputs)
    code, out = _json(capsys, ["singularities", name, q])
    assert code == 0 and out["modes"] and out["modes"][0]["verdict"] == "regular"
    uses = workspace_model(mech).options  # the others are refused (test_cli_errors)
    opts = (["--samples", "2000"] if "samples" in uses else []) + (
        ["--n", "31"] if "n" in uses else []
    )
    code, out = _json(capsys, ["workspace", name, *opts, "--plot", str(tmp_path / "w.png")])
    assert code == 0 and (tmp_path / "w.png").stat().st_size > 1000
    code, out = _json(capsys, ["accuracy", name])
    assert code == 0 and out["rows"] and np.isfinite(out["rows"][0]["nonlinear_output"])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["singularities", "rcm_bevel"],
            "singularities needs exactly one of --q, --pose (--xyz) or --grid",
        ),
        (["singularities", "rcm_bevel", "--q", "0,0,0.1"], "--q has 3 values; valid: exactly 6"),
        (
            ["singularities", "rcm_bevel", "--grid", "1"],
            "--grid '1'; valid: i,j[,N] with integers, e.g. 1,2,41",
        ),
        (
            ["singularities", "rcm_bevel", "--grid", "1,7"],
            "grid coordinates 1,7; valid: two different numbers in 1..6",
        ),
        (["workspace", "rcm_bevel", "--samples", "10"], "--samples 10; valid: 1000..5000000"),
        (
            ["singularities", "rcm_bevel", "--grid"],
            "rcm_bevel maps over two coordinates; valid: --grid i,j[,N], e.g. 1,2,41",
        ),
        (
            ["singularities", "rcm_bevel", "--grid", "1,2,1000"],
            "grid of 1000x1000 cells; valid: at most 250000 cells",
        ),
        (["accuracy", "rcm_belt", "--q", "0,0"], "--q has 2 values; valid: exactly 6"),
    ],
)
def test_typed_errors(capsys, argv, message):
    code, out = _json(capsys, argv)
    assert code == 2
    assert out["error"]["message"] == message
