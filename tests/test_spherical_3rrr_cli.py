"""``rcm-pin ik | fk spherical_3rrr``: rotation targets (--rpy, --rotation) and their errors.

Second route: the family's closed form (tan(φ/2) roots) and the rotation R = Rz(γ)Ry(β)Rx(α)
built here from the angles; the fk → ik round trip closes the loop through the CLI.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import EXACT, SOLVER

from rcm_pin.cli import main
from rcm_pin.rotations import rpy_to_matrix

ANGLES = (0.3, 0.4, 0.5)  # α, β, γ [rad]


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def csv(values) -> str:
    return ",".join(repr(float(v)) for v in np.asarray(values).ravel())


def test_ik_rpy_and_rotation_agree_and_reach_the_target(capsys):
    R = rpy_to_matrix(*ANGLES)
    code_a, out_a, _ = run(capsys, "ik", "spherical_3rrr", f"--rpy={csv(ANGLES)}", "--json")
    code_b, out_b, _ = run(capsys, "ik", "spherical_3rrr", f"--rotation={csv(R)}", "--json")
    a, b = json.loads(out_a), json.loads(out_b)
    assert code_a == code_b == 0 and a["count"] == b["count"] == 8
    assert [s["mode"] for s in a["solutions"]] == ["+++", "++-", "+-+", "+--",
                                                  "-++", "-+-", "--+", "---"]  # fmt: skip
    for sa, sb in zip(a["solutions"], b["solutions"], strict=True):
        assert list(sa["drives"]) == ["u1", "u2", "u3"] == a["drive_names"]
        np.testing.assert_allclose(np.array(sa["rotation"]), R, atol=SOLVER)
        np.testing.assert_allclose(sa["output"]["angles"], ANGLES, atol=SOLVER)
        np.testing.assert_allclose(list(sa["drives"].values()), list(sb["drives"].values()),
                                   atol=EXACT)  # fmt: skip
        assert sa["residual"] < EXACT
    assert a["rotation_projection_distance"] < EXACT and not a["position_only"]


def test_ik_drives_match_the_corrected_f1_to_f3(capsys):
    from rcm_pin.mechanisms.spherical_3rrr import paper

    _, out, _ = run(capsys, "ik", "spherical_3rrr", f"--rpy={csv(ANGLES)}", "--json")
    phi = np.array(list(json.loads(out)["solutions"][0]["drives"].values()))
    np.testing.assert_allclose(np.tan(phi), paper.tan_phi(*ANGLES)["corrected"], rtol=1e-10)


def test_fk_all_then_ik_returns_every_assembly_mode(capsys):
    code, out, _ = run(capsys, "fk", "spherical_3rrr", "--q", "0.1,0.2,0.3", "--all", "--json")
    direct = json.loads(out)
    assert code == 0 and direct["count"] == 4
    for sol in direct["solutions"]:
        R = np.array(sol["rotation"])
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=EXACT)
        code, out, _ = run(capsys, "ik", "spherical_3rrr", f"--rotation={csv(R)}", "--json")
        drives = np.array([list(s["drives"].values()) for s in json.loads(out)["solutions"]])
        assert code == 0
        assert np.min(np.abs(drives - [0.1, 0.2, 0.3]).max(axis=1)) < SOLVER


def test_rotation_is_projected_within_tolerance(capsys):
    R = rpy_to_matrix(*ANGLES) + 1e-4  # 3e-4 from SO(3), inside ROTATION_TOL = 1e-2
    code, out, _ = run(capsys, "ik", "spherical_3rrr", f"--rotation={csv(R)}", "--json")
    payload = json.loads(out)
    assert code == 0 and 1e-5 < payload["rotation_projection_distance"] < 1e-2


NOT_ROTATION = (
    "--rotation: matrix is not a rotation: distance to the nearest rotation {d} exceeds the "
    "tolerance 0.01 (Frobenius norm ||R - R_proj||); valid: an orthonormal matrix with "
    "determinant +1, r11,r12,r13,r21,...,r33 row by row"
)
VALID_ROTATION = "valid: --rpy alpha,beta,gamma, --rotation r11,...,r33 or --pose r11,...,r33"


@pytest.mark.parametrize(
    ("argv", "kind", "message"),
    [
        (["ik", "spherical_3rrr", "--rotation", "1,0,0,0,1,0,0,0,1.2"], "NotARotationError",
         NOT_ROTATION.format(d="0.2")),
        (["ik", "spherical_3rrr", "--rotation", "1,0,0,0,1,0,0,0,-1"], "NotARotationError",
         NOT_ROTATION.format(d="2")),
        (["ik", "spherical_3rrr", "--rotation", "1,0,0"], "InvalidInputError",
         "--rotation has 3 values; valid: exactly 9"),
        (["ik", "spherical_3rrr", "--rpy", "0,0"], "InvalidInputError",
         "--rpy has 2 values; valid: exactly 3"),
        (["ik", "spherical_3rrr", "--rpy", "0,0,0", "--rotation", "1,0,0,0,1,0,0,0,1"],
         "InvalidInputError", "--rpy conflicts with --rotation; valid: one of them"),
        (["ik", "spherical_3rrr", "--pose", "1,0,0,0,1,0,0,0,1", "--rotation",
          "1,0,0,0,1,0,0,0,1"], "InvalidInputError",
         "--pose conflicts with --rotation; valid: one of them"),
        (["ik", "spherical_3rrr", "--pose", "1,0,0,0,1,0,0,0,1", "--rpy", "0,0,0"],
         "InvalidInputError", "--pose conflicts with --xyz / --rpy; valid: one of them"),
        (["ik", "spherical_3rrr", "--xyz", "0,0,0"], "InvalidInputError",
         "--xyz does not apply to spherical_3rrr: its output is the rotation of frame "
         f"platform_centre; {VALID_ROTATION}"),
        (["ik", "spherical_3rrr"], "InvalidInputError",
         f"ik of spherical_3rrr needs its output rotation; {VALID_ROTATION}"),
        (["ik", "planar_3rrr", "--rpy", "0,0,0.1"], "InvalidInputError",
         "closed mechanisms take --pose x,y,rz; planar_3rrr has no tool pose for --xyz and no "
         "rotation output for --rpy / --rotation"),
        (["ik", "four_bar", "--rotation", "1,0,0,0,1,0,0,0,1"], "InvalidInputError",
         "closed mechanisms take --pose rz; four_bar has no tool pose for --xyz and no "
         "rotation output for --rpy / --rotation"),
        (["ik", "rcm_bevel", "--rotation", "1,0,0,0,1,0,0,0,1"], "InvalidInputError",
         "ik needs --pose, or --xyz (with --rpy or --rotation for the orientation)"),
        (["ik", "rcm_bevel", "--xyz", "0,0,0.09", "--rpy", "0,0,0", "--rotation",
          "1,0,0,0,1,0,0,0,1"], "InvalidInputError",
         "--rpy conflicts with --rotation; valid: one of them"),
        (["ik", "spherical_3rrr", "--rpy", "0,0,1e7"], "InvalidInputError",
         "--rpy has an angle of magnitude 1e+07 rad; valid: |angle| <= 1e+06 rad (larger "
         "angles are meaningless)"),
    ],
)  # fmt: skip
def test_bad_rotation_targets_are_typed_errors(capsys, argv, kind, message):
    code, out, _ = run(capsys, *argv, "--json")
    error = json.loads(out)["error"]
    assert (code, error["type"], error["message"]) == (2, kind, message)


def test_serial_tool_pose_takes_rotation_with_xyz(capsys):
    R = rpy_to_matrix(0.1, 0.2, 0.3)
    base = ["ik", "rcm_bevel", "--xyz", "0.02,-0.03,0.09", "--json"]
    _, out_a, _ = run(capsys, *base, "--rpy", "0.1,0.2,0.3")
    code, out_b, _ = run(capsys, *base, f"--rotation={csv(R)}")
    qa = [s["q"] for s in json.loads(out_a)["solutions"]]
    qb = [s["q"] for s in json.loads(out_b)["solutions"]]
    assert code == 0 and len(qa) == len(qb) > 0
    np.testing.assert_allclose(qa, qb, atol=EXACT)
    for sol in json.loads(out_b)["solutions"]:
        np.testing.assert_allclose(np.array(sol["rotation"]), R, atol=SOLVER)
