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
    import rcm_pin
    from rcm_pin.mechanisms.planar_3rrr import geometry
    from rcm_pin.mechanisms.planar_3rrr import workspace as ws

    g = geometry(rcm_pin.load("planar_3rrr"))
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
    (run,) = out["runs"]
    assert code == 0 and out["scenario"] == "circle" and run["status"] == "completed"
    assert run["max_closure_residual"] < 1e-9
    assert run["max_deviation_from_error_dynamics"] < 1e-6
    assert (tmp_path / "deviation.png").stat().st_size > 5000


def test_simulate_five_bar(capsys, tmp_path):
    code, out = _json(capsys, ["simulate", "five_bar", "--plot", str(tmp_path)])
    (run,) = out["runs"]
    assert code == 0 and run["status"] == "completed" and run["time_on_extras"] > 0
    assert max(run["peak_effort"]) <= 0.5 + 1e-12 and run["max_error_after_transient"] < 1e-4
    assert (tmp_path / "deviation.png").stat().st_size > 5000
    code, out = _json(capsys, ["simulate", "five_bar", "--no-switching", "--tau-max", "0.5"])
    (run,) = out["runs"]
    assert run["time_on_extras"] == 0 and run["max_error_after_transient"] > 1e-3


def test_simulate_five_bar_compare(capsys):
    code, out = _json(capsys, ["simulate", "five_bar", "--compare"])
    free, limited, switching = out["runs"]
    assert code == 0 and max(free["peak_effort"]) > 10 * max(switching["peak_effort"])
    assert limited["max_error_after_transient"] > 5 * switching["max_error_after_transient"]


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
            "singularities needs exactly one of --q, --pose (--xyz) or --grid",
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
            "planar_3rrr: pose [2.0, 0.0, 0.0] is outside the workspace (a leg cannot reach its "
            "platform point: |l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 fails)",
        ),
        (
            ["singularities", "five_bar", "--grid", "1,2"],
            "InvalidInputError",
            "five_bar maps over its workspace; valid: --grid without coordinates",
        ),
        (
            ["singularities", "five_bar", "--pose", "0,0.2", "--plot", "x.png"],
            "InvalidInputError",
            "--plot needs --grid",
        ),
        (
            ["singularities", "rcm_bevel", "--grid"],
            "InvalidInputError",
            "rcm_bevel maps over two coordinates; valid: --grid i,j[,N], e.g. 1,2,41",
        ),
        (
            ["singularities", "rcm_bevel", "--pose", "0,0,0"],
            "InvalidInputError",
            "--pose for rcm_bevel is a 3x4 tool pose 'r11,r12,r13,x;...;r31,r32,r33,z'",
        ),
        (
            ["workspace", "planar_3rrr", "--n", "3"],
            "InvalidInputError",
            "grid size 3; valid: 5..1001 points per side",
        ),
        (
            ["workspace", "planar_3rrr", "--phi-range", "1,0"],
            "InvalidInputError",
            "phi range 1,0; valid: finite lo <= hi within one turn (hi − lo <= 2π) [rad]",
        ),
        (
            ["simulate", "planar_3rrr", "--tau-zeta=-1,1"],
            "InvalidInputError",
            "tau=-1.0, zeta=1.0 are invalid; valid: tau > 0 [s], zeta >= 0",
        ),
        (
            ["simulate", "planar_3rrr", "--switching"],
            "InvalidInputError",
            "--switching / --compare need extra drives; planar_3rrr has none",
        ),
        (
            ["simulate", "five_bar", "--tau-max", "0"],
            "InvalidInputError",
            "--tau-max 0.0 is invalid; valid: > 0 [N*m, N]",
        ),
        (
            ["simulate", "five_bar", "--scenario", "nope"],
            "InvalidInputError",
            "unknown scenario 'nope' for five_bar; valid: crossing, home_circle",
        ),
        (
            ["simulate", "rcm_bevel", "--switching"],
            "InvalidInputError",
            "--switching / --compare need extra drives; rcm_bevel has none",
        ),
        (
            ["view", "planar_3rrr", "--q", "1.6,-0.4,3.6", "--html", "x.html"],
            "UnreachablePoseError",
            "planar_3rrr: drives [1.6, -0.4, 3.6] admit no assembly (the loops cannot close); "
            "valid: drive values inside the workspace of planar_3rrr",
        ),
    ],
)
def test_closed_errors(capsys, argv, error, message):
    code, out = _json(capsys, argv)
    assert code == 2
    assert out["error"] == {"type": error, "message": message}
