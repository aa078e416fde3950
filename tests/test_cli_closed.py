"""Closed-loop paths of ``rcm-pin singularities | workspace | simulate | view``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rcm_pin.cli import main

Q3 = "--q=-0.2059,-2.481,1.671"  # drives of mode +++ at pose (0.02, 0.01, 0.1)


def _json(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_singularities_pose_every_mode(capsys):
    code, out = _json(capsys, ["singularities", "planar_3rrr", "--pose", "0.02,0.01,0.1"])
    assert code == 0 and out["tol"] == 1e-8
    assert [m["mode"] for m in out["modes"]] == [
        "+++",
        "++-",
        "+-+",
        "+--",
        "-++",
        "-+-",
        "--+",
        "---",
    ]
    for m in out["modes"]:
        assert m["verdict"] == "regular" and m["screw_agrees"] and m["residual"] < 1e-12
        assert len(m["sigma_A"]) == len(m["sigma_B"]) == 3 and abs(m["det_A"]) > 1e-3


def test_singularities_pose_on_type2_curve(capsys):
    from rcm_pin.closed_loop import load_closed
    from rcm_pin.closed_loop import planar_3rrr as p3
    from rcm_pin.closed_loop import workspace as ws

    g = p3.Geometry3RRR.from_params(load_closed("planar_3rrr").params)
    pose = ws.type2_points(g, 0.0, 0, max_points=1)[0]
    code, out = _json(
        capsys,
        ["singularities", "planar_3rrr", "--pose=" + ",".join(repr(float(v)) for v in pose)]
        + ["--mode", "+++"],
    )
    (m,) = out["modes"]
    assert code == 0 and m["type2"] and not m["type1"] and m["verdict"] == "type 2"
    assert m["screw"]["type2"] and m["screw_agrees"] and abs(m["det_A"]) < 1e-8


def test_singularities_drives_five_bar_and_text(capsys):
    code, out = _json(capsys, ["singularities", "planar_3rrr", Q3])
    assert code == 0 and len(out["modes"]) >= 2
    assert all(m["verdict"] == "regular" and m["screw_agrees"] for m in out["modes"])
    code, out = _json(capsys, ["singularities", "five_bar", "--pose", "0,0.2", "--mode", "1"])
    assert code == 0 and [m["mode"] for m in out["modes"]] == ["+-"]
    assert main(["singularities", "five_bar", "--pose", "0,0.2"]) == 0
    assert "mode --: regular" in capsys.readouterr().out


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar"])
def test_singularities_grid_png(capsys, tmp_path, name):
    png = tmp_path / "map.png"
    code, out = _json(
        capsys, ["singularities", name, "--grid", "--n", "41", "--mode", "1", "--plot", str(png)]
    )
    assert code == 0 and png.stat().st_size > 5000 and out["plot"] == str(png)
    det_a = np.array(out["det_A"], dtype=float)  # null (outside) -> nan
    assert det_a.shape == (41, 41) and np.isnan(det_a).any() and np.isfinite(det_a).any()
    assert out["type2_sign_changes"] > 0 and out["reachable_area"] > 0.05


def test_workspace_areas(capsys, tmp_path):
    png = tmp_path / "ws.png"
    code, out = _json(
        capsys,
        ["workspace", "planar_3rrr", "--n", "41", "--phi-range=-0.5,0.5", "--plot", str(png)],
    )
    assert code == 0 and png.stat().st_size > 5000
    assert 0 < out["total_area"] <= out["constant_orientation_area"] <= out["reachable_area"]
    assert out["orientations"] == 29
    code, out = _json(capsys, ["workspace", "five_bar", "--n", "41"])
    assert code == 0 and out["total_area"] == out["constant_orientation_area"] > 0.1


def test_simulate_planar_3rrr(capsys, tmp_path):
    argv = ["simulate", "planar_3rrr", "--duration", "0.4", "--plot", str(tmp_path)]
    code, out = _json(capsys, argv)
    assert code == 0 and out["max_closure_residual"] < 1e-9
    assert out["max_deviation_from_error_dynamics"] < 1e-6
    assert (tmp_path / "planar_3rrr_tracking.png").stat().st_size > 5000


def test_simulate_five_bar(capsys, tmp_path):
    code, out = _json(capsys, ["simulate", "five_bar", "--plot", str(tmp_path)])
    (run,) = out["runs"]
    assert code == 0 and run["completed"] and run["time_on_extras"] > 0
    assert run["peak_main_torque"] <= 0.5 + 1e-12 and run["max_error_after_transient"] < 1e-4
    assert (tmp_path / "five_bar_switching.png").stat().st_size > 5000
    code, out = _json(capsys, ["simulate", "five_bar", "--no-switching", "--tau-max", "0.5"])
    (run,) = out["runs"]
    assert run["time_on_extras"] == 0 and run["max_error_after_transient"] > 1e-3


def test_view_closed_html(capsys, tmp_path):
    html = tmp_path / "v.html"
    code, out = _json(capsys, ["view", "planar_3rrr", Q3, "--html", str(html)])
    assert code == 0 and out["closure_gap"] < 1e-12 and len(out["q_full"]) == 7
    assert html.stat().st_size > 10_000


@pytest.mark.parametrize(
    ("argv", "error", "message"),
    [
        (
            ["singularities", "planar_3rrr"],
            "InvalidInputError",
            "singularities planar_3rrr needs exactly one of --pose, --q or --grid",
        ),
        (
            ["singularities", "planar_3rrr", "--pose", "0,0"],
            "InvalidInputError",
            "--pose has 2 values; valid: exactly 3",
        ),
        (
            ["singularities", "planar_3rrr", "--pose", "0,0,0", "--mode", "9"],
            "InvalidInputError",
            "mode '9' is not a working mode of planar_3rrr; valid: 0..7 or "
            "+++, ++-, +-+, +--, -++, -+-, --+, ---",
        ),
        (
            ["singularities", "planar_3rrr", "--pose", "2,0,0"],
            "UnreachablePoseError",
            "planar_3rrr: pose [2.0, 0.0, 0.0] is outside the workspace (a leg cannot reach it)",
        ),
        (
            ["singularities", "five_bar", "--grid", "1,2"],
            "InvalidInputError",
            "--grid takes no value for closed mechanisms (got '1,2'); "
            "valid: --grid [--mode M] [--phi PHI] [--n N]",
        ),
        (
            ["singularities", "five_bar", "--pose", "0,0.2", "--plot", "x.png"],
            "InvalidInputError",
            "--plot needs --grid",
        ),
        (
            ["singularities", "rcm_bevel", "--grid"],
            "InvalidInputError",
            "--grid needs i,j[,N] for serial mechanisms, e.g. --grid 1,2,41",
        ),
        (
            ["singularities", "rcm_bevel", "--pose", "0,0,0"],
            "InvalidInputError",
            "--pose apply to closed mechanisms only; valid for rcm_bevel: "
            "see rcm-pin singularities --help",
        ),
        (
            ["workspace", "planar_3rrr", "--n", "3"],
            "InvalidInputError",
            "grid size 3; valid: >= 5 points per side",
        ),
        (
            ["workspace", "planar_3rrr", "--phi-range", "1,0"],
            "InvalidInputError",
            "phi range 1.0,0.0; valid: lo <= hi, finite [rad]",
        ),
        (
            ["simulate", "planar_3rrr", "--tau-zeta=-1,1"],
            "InvalidInputError",
            "--tau-zeta -1,1 is invalid; valid: tau > 0 [s], zeta > 0",
        ),
        (
            ["simulate", "planar_3rrr", "--switching"],
            "InvalidInputError",
            "--switching applies to five_bar only, not planar_3rrr",
        ),
        (
            ["simulate", "five_bar", "--tau-max", "0"],
            "InvalidInputError",
            "--tau-max 0.0 is invalid; valid: > 0 [N*m]",
        ),
        (
            ["simulate", "rcm_bevel", "--switching"],
            "InvalidInputError",
            "--switching applies to five_bar only; rcm_bevel is serial",
        ),
        (
            ["view", "planar_3rrr", "--q", "1.6,-0.4,3.6", "--html", "x.html"],
            "UnreachablePoseError",
            "planar_3rrr: drives [1.6, -0.4, 3.6] admit no assembly (loop cannot close)",
        ),
        (
            ["view", "planar_3rrr", Q3, "--assembly", "9", "--html", "x.html"],
            "InvalidInputError",
            "assembly 9 out of range; valid: 0..1 (2 assembly modes for these drives)",
        ),
        (
            ["view", "rcm_bevel", "--assembly", "1", "--html", "x.html"],
            "InvalidInputError",
            "--assembly applies to closed mechanisms only; rcm_bevel is serial",
        ),
    ],
)
def test_closed_errors(capsys, argv, error, message):
    code, out = _json(capsys, argv)
    assert code == 2
    assert out["error"] == {"type": error, "message": message}
