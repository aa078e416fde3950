"""Cost bounds of the CLI: sweep / optimize sizes and rcm-track steps are refused with the
estimate and the bound (exit status 2) while parsing, before any work."""

from __future__ import annotations

import json

import pytest

from rcm_pin.cli import main


def _error(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)["error"]


VARY = ["--vary", "q2_limit=0.6:1.4:1000", "--vary", "q3_lower=0.02:0.07:1000"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["sweep", "rcm_bevel", *VARY, "--vary", "q3_upper=0.1:0.2:1000"],
            "1000000000 designs would take about 1.67e+05 h on one core (about 0.6 s a design); "
            "valid: at most 1000000 designs",
        ),
        (
            ["sweep", "rcm_bevel", "--vary", "q2_limit=0.6:1.4", "--sampler", "lhs",
             "--samples", "1000001"],
            "1000001 designs would take about 167 h on one core (about 0.6 s a design); "
            "valid: at most 1000000 designs",
        ),
        (
            ["optimize", "rcm_bevel", "--vary", "q2_limit=0.6:1.4", "--trials", "10000000"],
            "10000000 trials would take about 1.67e+03 h on one core (about 0.6 s a design); "
            "valid: at most 1000000 trials",
        ),
    ],
    ids=["grid", "lhs", "optimize"],
)  # fmt: skip
def test_study_sizes_are_bounded(capsys, argv, message):
    code, error = _error(capsys, [*argv, "--metric", "cone_coverage"])
    assert code == 2 and error == {"type": "InvalidInputError", "message": message}


def test_rcm_track_steps_are_bounded(capsys):
    code, error = _error(capsys, ["rcm-track", "panda", "--path", "spiral", "--rate", "100000"])
    assert code == 2 and error["type"] == "InvalidInputError"
    assert error["message"] == (
        "rate 100000 Hz over 6 s is 600000 control steps; valid: at most 100000 (measured on "
        "panda: about 0.5 ms and 4 kB per step with its JSON output, so 100000 steps take about "
        "a minute and 400 MB); lower the rate or the duration"
    )


def test_rcm_track_at_the_step_bound_is_not_refused_by_it():
    from rcm_pin.studies.surgical_paths import MAX_STEPS, Cone, surgical_path

    cone = Cone(apex=(0.0, 0.0, 0.0), direction=(0.0, 0.0, -1.0))
    path = surgical_path("circle", cone, rate=MAX_STEPS / 4.0)
    assert len(path.t) == MAX_STEPS + 1
