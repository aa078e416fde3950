"""``rcm-pin`` on the LAAS-style fixtures (tests/data/laas) with ``--json``: one JSON
document, exit 0, 2 for bad input; each result checked by a second route."""

from __future__ import annotations

import json

import numpy as np
import pytest
from laas_fixtures import DATA, FIXTURES, OUTPUT, SIMULATE, no_output_message

import rcm_pin
from rcm_pin.cli import main


def _json(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def _path(name: str) -> str:
    return str(DATA / f"{name}.urdf")


def _drives(mech) -> str:
    return ",".join(repr(float(v)) for v in mech.home[mech.loops.drive_q])


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_fk_every_mode_is_assembled(capsys, name):
    mech = rcm_pin.load(_path(name))
    code, out = _json(capsys, ["fk", _path(name), "--q", _drives(mech), "--all"])
    assert code == 0 and out["output_coords"] == [] and out["output_frame"] == ""
    assert len(out["solutions"]) >= FIXTURES[name]["min_modes"]
    for s in out["solutions"]:  # second route: the closure residual recomputed
        assert np.max(np.abs(mech.closure_residual(mech.q_pin(np.array(s["q"]))))) < 1e-12


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_singularities_without_and_with_output(capsys, name):
    mech = rcm_pin.load(_path(name))
    code, out = _json(capsys, ["singularities", _path(name), "--q", _drives(mech)])
    assert code == 0 and out["modes"]
    assert all(m["type1"] is None and m["verdict"].startswith("regular") for m in out["modes"])
    frame, _ = OUTPUT[name]
    code, out = _json(capsys, ["singularities", _path(name), "--q", _drives(mech), *SIMULATE[name]])
    assert code == 0 and all(m["residual"] < 1e-12 for m in out["modes"])
    assert any(m["verdict"] == "regular" for m in out["modes"])


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_ik_needs_an_output_and_ocp_ik_agrees_with_ik(capsys, name):
    mech = rcm_pin.load(_path(name))
    code, out = _json(capsys, ["ik", _path(name), "--pose", "0,0"])
    assert code == 2 and out["error"] == {
        "type": "UnknownFrameError",
        "message": no_output_message(mech, "a target"),
    }
    frame, _ = OUTPUT[name]
    with_out = rcm_pin.load(_path(name), output_frame=frame)
    target = with_out.output_value(with_out.q_pin(with_out.home))
    pose = ",".join(repr(float(v)) for v in target)
    code, ik = _json(capsys, ["ik", _path(name), "--tool-frame", frame, "--pose", pose])
    assert code == 0 and ik["solutions"]
    code, nlp = _json(capsys, ["ocp", "ik", _path(name), "--tool-frame", frame, "--pose", pose])
    assert code == 0 and nlp["success"] and nlp["closure_residual"] < 1e-9
    np.testing.assert_allclose(list(nlp["output"].values()), target, atol=1e-9)
    gaps = [
        np.max(np.abs(np.angle(np.exp(1j * (np.array(nlp["q"]) - np.array(s["q"]))))))
        for s in ik["solutions"]
    ]
    assert min(gaps) < 1e-6  # the NLP's solution is one of the working modes of ik


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_simulate_needs_an_output_then_tracks_it(capsys, name):
    mech = rcm_pin.load(_path(name))
    code, out = _json(capsys, ["simulate", _path(name), "--duration", "0.1"])
    assert code == 2 and out["error"]["message"] == no_output_message(
        mech, "a simulation (its task)"
    )
    code, out = _json(capsys, ["simulate", _path(name), "--duration", "0.1", *SIMULATE[name]])
    (run,) = out["runs"]
    assert code == 0 and run["status"] == "completed"
    assert run["max_closure_residual"] < 1e-9 and run["rms_error"] < 1e-6


def test_output_flags_conflict_and_bad_coords(capsys):
    code, out = _json(
        capsys, ["fk", _path("five_bar"), "--q", "0,0", "--tool-frame", "base",
                 "--output-frame", "effector"]
    )  # fmt: skip
    assert code == 2 and out["error"]["message"] == (
        "output_frame 'effector' conflicts with tool_frame 'base'; valid: one of them (they "
        "name the same frame)"
    )
    code, out = _json(capsys, ["fk", _path("five_bar"), "--q", "0,0", "--output-frame", "nope"])
    assert code == 2 and out["error"]["type"] == "UnknownFrameError"
    assert out["error"]["message"].startswith("unknown output frame 'nope' in five_bar; valid: ")


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_vibrations_at_drive_values_without_output(capsys, name):
    mech = rcm_pin.load(_path(name))
    argv = ["vibrations", _path(name), "--q", _drives(mech), "--stiffness", "10", "--check"]
    code, out = _json(capsys, argv)
    assert code == 0 and out["mode"] == "assembly_0" and len(out["frequencies"]) == mech.loops.dof
    assert out["max_relative_difference"] < 1e-5  # second route: linearised dynamics
    code, out = _json(capsys, [*argv, "--mode", "nope"])
    assert code == 2 and out["error"]["message"].startswith(
        f"mode 'nope' is not an assembly mode of {name} at these drives; valid: assembly_0, "
    )
