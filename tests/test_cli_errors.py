"""The command line refuses bad input with one typed line (exit 2) or, with ``--json``, one
JSON error document; output paths are checked before any work; nothing is ignored."""

from __future__ import annotations

import json

import pytest

from rcm_pin.cli import main
from rcm_pin.report.sections import SECTIONS

Q = "0,0,0.08,0,0.3,0"


def run_json(capsys, *argv):
    code = main([*argv, "--json"])
    out = capsys.readouterr()
    return code, json.loads(out.out), out.err


@pytest.mark.parametrize(
    ("argv", "kind", "message"),
    [
        (
            ["fk", "rcm_bevel"],
            "UsageError",
            "rcm-pin fk: the following arguments are required: --q",
        ),
        (
            ["reproduce", "--only", "zzzz"],
            "InvalidInputError",
            "--only 'zzzz' matches no report section; valid: a word of "
            + ", ".join(name for name, _ in SECTIONS),
        ),
        (
            ["urdf", "rcm_bevel", "-o", "/nonexistent-dir/x/y.urdf"],
            "InvalidInputError",
            "-o '/nonexistent-dir/x/y.urdf': folder '/nonexistent-dir/x' does not exist; valid: a "
            "path in an existing folder",
        ),
        (
            ["view", "rcm_bevel", "--png", "/nonexistent-dir/x.png"],
            "InvalidInputError",
            "--png '/nonexistent-dir/x.png': folder '/nonexistent-dir' does not exist; valid: a "
            "path in an existing folder",
        ),
        (  # long fuzz profile: 1000² cells × 181 orientations took minutes
            ["workspace", "planar_3rrr", "--n", "1000"],
            "InvalidInputError",
            "a 1000 x 1000 grid at 181 orientations is 1.81e+08 inverse problems; valid: at most "
            "1e+07 (a smaller --n or a coarser phi step)",
        ),
        (  # long fuzz profile: 954 546 samples × 64 working modes ran over 30 s
            ["workspace", "translational_3ppapa", "--samples", "954546"],
            "InvalidInputError",
            "954546 workspace samples, each solved in all 64 working modes; valid: 1..250000 "
            "(about 15 s of work at the most)",
        ),
        (  # an option the family's workspace does not use is refused, not ignored
            ["workspace", "translational_3ppapa", "--phi", "0.15"],
            "InvalidInputError",
            "--phi does not apply to the workspace of translational_3ppapa; valid: --samples",
        ),
        (
            ["workspace", "four_bar", "--samples", "2000"],
            "InvalidInputError",
            "--samples does not apply to the workspace of four_bar; valid: no options",
        ),
        (  # long fuzz profile: np.arange over 1e147 rad raised a raw ValueError
            ["workspace", "planar_3rrr", "--phi-range=1000001.0,4.4e147"],
            "InvalidInputError",
            "phi range 1e+06,4.4e+147; valid: finite lo <= hi within one turn (hi − lo <= 2π) "
            "[rad]",
        ),
        (
            ["workspace", "rcm_bevel", "--phi", "0.1"],
            "InvalidInputError",
            "--phi applies to closed mechanisms; rcm_bevel is serial",
        ),
        (
            ["singularities", "rcm_bevel", "--grid", "2,5,11", "--n", "21"],
            "InvalidInputError",
            "--n applies to closed mechanisms; rcm_bevel is serial",
        ),
        (
            ["singularities", "planar_3rrr", "--grid", "--wide"],
            "InvalidInputError",
            "--wide applies to serial mechanisms; planar_3rrr is closed",
        ),
        (
            ["singularities", "planar_3rrr", "--pose", "0.02,0.01,0.1", "--task", "position"],
            "InvalidInputError",
            "--task applies to serial mechanisms; planar_3rrr is closed",
        ),
        (
            ["ik", "rcm_bevel", "--pose", "1,0,0,0;0,1,0,0;0,0,1,0.08", "--xyz", "0,0,0.08"],
            "InvalidInputError",
            "--pose conflicts with --xyz / --rpy; valid: one of them",
        ),
        (
            ["fk", "rcm_bevel", "--q", Q, "--all"],
            "InvalidInputError",
            "--all lists the assembly modes of closed mechanisms; rcm_bevel is serial",
        ),
    ],
)
def test_bad_input_is_one_json_error(capsys, argv, kind, message):
    code, payload, err = run_json(capsys, *argv)
    assert code == 2 and err == ""
    assert payload == {"error": {"type": kind, "message": message}}


def test_without_json_one_line_on_stderr(capsys):
    assert main(["fk", "rcm_bevel"]) == 2
    out = capsys.readouterr()
    assert out.out == ""
    assert out.err == (
        "rcm-pin: error: UsageError: rcm-pin fk: the following arguments are required: --q\n"
    )


def test_unknown_subcommand_is_a_usage_error(capsys):
    code, payload, _ = run_json(capsys, "bogus")
    assert code == 2 and payload["error"]["type"] == "UsageError"
    assert payload["error"]["message"].startswith("rcm-pin: argument COMMAND: invalid choice")


def test_reproduce_out_that_cannot_be_created(capsys, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    code, payload, _ = run_json(capsys, "reproduce", "--out", str(blocker), "--only", "position")
    assert code == 2
    assert payload["error"]["message"] == f"--out {str(blocker)!r} is a file; valid: a folder"
    code, payload, _ = run_json(capsys, "reproduce", "--out", "/proc/rcm-pin-report")
    assert code == 2
    assert payload["error"]["message"].startswith(
        "--out '/proc/rcm-pin-report': cannot create the folder ("
    )
    assert not (tmp_path / "report.md").exists()


def test_plot_path_that_is_a_folder(capsys, tmp_path):
    code, payload, _ = run_json(capsys, "workspace", "rcm_bevel", "--plot", str(tmp_path))
    assert code == 2
    assert (
        payload["error"]["message"] == f"--plot {str(tmp_path)!r} is a folder; valid: a file path"
    )


def test_negative_values_need_no_equals_sign(capsys):
    code, payload, _ = run_json(capsys, "fk", "rcm_bevel", "--q", "-0.2,0.1,0.08,0,0.3,0")
    assert code == 0 and payload["solutions"][0]["q"][0] == -0.2


def test_grid_size_is_refused_before_allocating(capsys):
    code, payload, _ = run_json(capsys, "singularities", "rcm_bevel", "--grid", "1,2,100000")
    assert code == 2
    assert payload["error"] == {
        "type": "InvalidInputError",
        "message": "grid of 100000x100000 cells; valid: at most 250000 cells",
    }


def test_within_limits_names_the_violated_limits(capsys):
    code, payload, _ = run_json(capsys, "ik", "rcm_bevel", "--xyz", "1,1,1", "--within-limits")
    assert code == 2 and payload["error"]["type"] == "UnreachablePoseError"
    assert payload["error"]["message"] == (
        "rcm_bevel: none of the 4 solutions of target x=1, y=1, z=1 lies within the joint limits "
        "(branch_0: q3 = 1.73205 > 0.12; branch_1: q1 = 2.35619 > 1.0472, q2 = 2.52611 > 1.0472, "
        "q3 = 1.73205 > 0.12; branch_2: q1 = 2.35619 > 1.0472, q3 = -1.73205 < 0.05; branch_3: "
        "q2 = -2.52611 < -1.0472, q3 = -1.73205 < 0.05); valid: a target with a solution inside "
        "the limits"
    )


def test_the_report_cites_the_papers_by_reference(tmp_path):
    from rcm_pin.report.writer import write_report

    text = write_report(tmp_path, only=["position"], quiet=True).read_text()
    assert "../shared" not in text and "seeds" not in text
    assert "## Sources" in text and "[004] S. V. Kheylo" in text
