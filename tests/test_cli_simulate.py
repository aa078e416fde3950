"""``rcm-pin simulate``."""

from __future__ import annotations

import json

import pytest

from rcm_pin.cli import main


def test_simulate_json(capsys, tmp_path):
    rc = main(
        [
            "simulate",
            "rcm_two_mass",
            "--arg",
            "q3_upper=0.3",
            "--duration",
            "0.3",
            "--json",
            "--plot",
            str(tmp_path),
        ]
    )
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    (run,) = out["runs"]
    assert out["scenario"] == "paper000" and run["status"] == "completed"
    assert run["gains"] == {"Kn": 720.0, "Kc": 12.0}
    assert len(out["figures"]) == 3 and (tmp_path / "phase.png").exists()


def test_simulate_text_tau_zeta(capsys):
    rc = main(
        [
            "simulate",
            "rcm_bevel_4dof",
            "--trajectory",
            "rig_circle",
            "--tau-zeta",
            "0.05,1",
            "--duration",
            "0.2",
            "--no-gravity",
        ]
    )
    assert rc == 0
    out = capsys.readouterr().out
    assert "rcm_bevel_4dof: scenario rig_circle" in out and "Kn = 400, Kc = 40, task space" in out
    assert "rig_circle: completed at 0.200 s" in out


def test_simulate_list(capsys):
    assert main(["simulate", "planar_3rrr", "--list", "--json"]) == 0
    assert set(json.loads(capsys.readouterr().out)["scenarios"]) == {"circle", "home_circle"}


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--gains", "720"], "--gains has 1 values; valid: exactly 2"),
        (["--tau-zeta=-1,1"], "tau=-1.0, zeta=1.0 are invalid; valid: tau > 0 [s], zeta >= 0"),
        (["--duration", "-1"], "--duration -1.0 is invalid; valid: >= 1e-09 [s]"),
        (["--duration", "5e-324"], "--duration 5e-324 is invalid; valid: >= 1e-09 [s]"),
        (
            ["--gains", "1e300,1e300"],
            "gains Kn=1e+300, Kc=1e+300 are too fast; valid: Kn <= 1e+08 [1/s^2], Kc <= 20000 "
            "[1/s] (error dynamics faster than 10000 rad/s make the explicit integrator's steps "
            "shorter than 0.1 ms; gains of 1e300 ran past two minutes for 0.05 s simulated)",
        ),
        (
            ["--tau-zeta", "1e-300,1"],
            "tau=1e-300 s is outside the valid range; valid: 0.0001 to 10000 s (a faster error "
            "dynamics makes the integrator's steps shorter than 0.1 ms)",
        ),
    ],
)
def test_simulate_errors(capsys, argv, message):
    rc = main(["simulate", "rcm_two_mass", "--json", *argv])
    assert rc == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err["type"] == "InvalidInputError" and err["message"] == message


def test_a_duration_over_the_time_budget_is_refused_after_a_probe(capsys):
    """1e9 s of simulated time: the 1 s probe's integration time, scaled, is far over the
    600 s budget; refused with the estimate and the longest run it allows."""
    from rcm_pin.cli import simulate

    rc = main(["simulate", "rcm_bevel", "--arg", "q3_upper=0.3", "--json", "--duration", "1e9"])
    err = json.loads(capsys.readouterr().out)["error"]
    assert rc == 2 and err["type"] == "InvalidInputError"
    message = err["message"]
    assert message.startswith("--duration 1e+09 s would take about ")
    assert "s per simulated second, measured on a 1 s probe); valid: at most about " in message
    assert message.endswith("s of simulated time for this run (a 600 s budget)")
    assert simulate.FREE_DURATION < 1e9


def test_a_duration_within_the_free_bound_runs_without_a_probe(capsys, monkeypatch):
    from rcm_pin.cli import simulate

    monkeypatch.setattr(simulate, "MAX_SECONDS", 0.0)  # any probe would refuse
    rc = main(["simulate", "rcm_bevel", "--arg", "q3_upper=0.3", "--json", "--duration", "0.2"])
    assert rc == 0 and json.loads(capsys.readouterr().out)["runs"][0]["duration"] > 0


def test_simulation_options_bound_the_samples():
    from rcm_pin.control import SimulationOptions
    from rcm_pin.errors import InvalidInputError

    with pytest.raises(InvalidInputError) as exc:
        SimulationOptions(samples=10**9)
    assert str(exc.value) == (
        "samples 1000000000; valid: 2 to 1000000 (memory: the result keeps each of its arrays "
        "per sample), or None for the solver's steps"
    )
