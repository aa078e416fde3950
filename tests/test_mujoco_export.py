"""The MuJoCo export proven right (issue 28, docs/mujoco.md).

For every catalogue mechanism and URDFs loaded by path: the file loads in MuJoCo without
warnings; MuJoCo's mass matrix and bias projected through the coupling equal rcm-pin's
(1e-9 relative: both are exact recursive algorithms, measured 1e-15); the rigid limit of
MuJoCo's constrained dynamics (its M, bias, efc_J and −J̇v) equals rcm-pin's constrained
forward dynamics (1e-9 relative, measured <= 1e-11); a 0.2 s free motion with the file's
solver settings stays within the predicted drift (rcm_pin.export.settings).
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin.dynamics.constrained import world_closure
from rcm_pin.errors import InvalidInputError, MissingExtraError, UnknownMechanismError
from rcm_pin.export import check, settings, to_mjcf
from rcm_pin.model.coupling import mimic_tags

DATA = Path(__file__).resolve().parent / "data"
#: URDFs loaded by path, with their tool frames
PATHS = {"rcm_wrist_arm.urdf": "tool", "mimic_tree.urdf": "tool_link"}
PATHS["continuous_joints.urdf"] = "tool_link"
SOLVER = 1e-9
#: the closed mechanisms of the catalogue (test_closed_list_is_the_catalogues keeps it true)
CLOSED = (
    "planar_3rrr",
    "five_bar",
    "four_bar",
    "eye_4dof",
    "spherical_3rrr",
    "translational_3ppapa",
    "translational_3ppapa_loops",
)


def _export(mech, folder):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", settings.InertiaFloorWarning)
        warnings.simplefilter("ignore", settings.InexactExportWarning)
        export = to_mjcf(mech, folder / f"{mech.name}.xml")
    return export, check.load_mujoco(export.path, export.mechanism)


@pytest.fixture(scope="module", params=[*rcm_pin.names(), *PATHS])
def exported(request, tmp_path_factory):
    name = request.param
    mech = rcm_pin.load(str(DATA / name), tool_frame=PATHS[name]) if name in PATHS else None
    mech = mech or rcm_pin.load(name)
    return _export(mech, tmp_path_factory.mktemp("mjcf"))


@pytest.fixture(scope="module", params=CLOSED)
def exported_closed(request, tmp_path_factory):
    return _export(rcm_pin.load(request.param), tmp_path_factory.mktemp("mjcf"))


def test_closed_list_is_the_catalogues():
    assert set(CLOSED) == {n for n in rcm_pin.names() if rcm_pin.load(n).is_closed}


def test_loads_without_warnings(exported):
    import mujoco

    export, mj = exported
    mech = export.mechanism
    check.set_state(mj, mech, mech.to_pin(mech.home), np.zeros(mech.model.nv))
    mujoco.mj_forward(mj.model, mj.data)
    assert not any(w.number for w in mj.data.warning)


def test_meshes_are_referenced_by_absolute_path(tmp_path):
    export, mj = _export(rcm_pin.load("panda"), tmp_path)
    files = [m.get("file") for m in ET.parse(export.path).getroot().iter("mesh")]
    assert files and all(Path(f).is_absolute() and Path(f).is_file() for f in files)
    assert mj.model.nmesh == len(files)


def test_mass_matrix_and_bias_match_through_the_coupling(exported):
    export, mj = exported
    rng = np.random.default_rng(28)
    for q, v, _ in check.random_states(export.mechanism, rng):
        assert check.tree_error(mj, export.mechanism, q, v) <= SOLVER


def test_rigid_limit_matches_constrained_forward_dynamics(exported_closed):
    export, mj = exported_closed
    rng = np.random.default_rng(29)
    for q, v, tau in check.random_states(export.mechanism, rng):
        assert check.rigid_limit_error(mj, export.mechanism, q, v, tau) <= SOLVER


def test_free_motion_stays_within_the_predicted_drift(exported):
    export, mj = exported
    mech = export.mechanism
    q, v, _ = check.random_states(mech, np.random.default_rng(30), n=1)[0]
    drift = check.free_motion_drift(mj, mech, q, v, duration=0.2)
    assert drift <= export.settings.predicted_drift
    if export.settings.predicted_drift:
        assert export.settings.predicted_drift <= export.settings.drift_tol


def test_jdot_v_is_in_efc_aref_and_leaving_it_out_is_wrong(tmp_path):
    """MuJoCo's efc_aref less its spring terms is −J̇v (rcm-pin's −γ); a rigid limit
    without it is off by far more than the tolerance."""
    import mujoco

    mech = rcm_pin.load("four_bar")
    export, mj = _export(mech, tmp_path)
    q, v, tau = check.random_states(mech, np.random.default_rng(31), n=1)[0]
    check.set_state(mj, mech, q, v)
    mujoco.mj_forward(mj.model, mj.data)
    d = mj.data
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    k, b, imp = d.efc_KBIP[eq, 0], d.efc_KBIP[eq, 1], d.efc_KBIP[eq, 2]
    minus_jdot_v = d.efc_aref[eq] + b * d.efc_vel[eq] + k * imp * d.efc_pos[eq]
    rows = list(mech.loops.closures[0].world_rows)
    gamma = world_closure(mech, q, v)[2]
    np.testing.assert_allclose(minus_jdot_v[rows], -gamma, rtol=SOLVER, atol=1e-12)
    good = check.rigid_acceleration(mj, mech, q, v, tau)
    bad = check.rigid_acceleration(mj, mech, q, v, tau, jdot=False)
    assert np.linalg.norm(bad - good) > 1e-6 * np.linalg.norm(good)


def test_the_file_says_what_the_mechanism_is(tmp_path):
    mech = rcm_pin.load("translational_3ppapa")
    export, _ = _export(mech, tmp_path)
    root = ET.parse(export.path).getroot()
    joints = {e.get("joint1"): e.get("polycoef") for e in root.iter("joint") if e.get("joint1")}
    for name, (_primary, mult, off) in mimic_tags(mech.urdf).items():
        assert [float(x) for x in joints[name].split()] == [off, mult, 0, 0, 0]
    connects = [(e.get("site1"), e.get("site2")) for e in root.iter("connect")]
    assert connects == [(c.frame_a, c.frame_b) for c in mech.loops.closures]
    assert [m.get("joint") for m in root.iter("motor")] == list(mech.loops.drives)
    sites = {s.get("name") for s in root.iter("site")}
    assert mech.output.frame in sites
    option = root.find("option")
    assert float(option.get("timestep")) == export.settings.timestep
    text = export.path.read_text()
    comment = text[text.index("<!-- rcm-pin export") : text.index("-->")]
    assert "2*timestep" in comment and f"timestep {export.settings.timestep:g} s" in comment
    for eq in [*root.iter("connect"), *(e for e in root.iter("joint") if e.get("joint1"))]:
        assert eq.get("solimp").split()[0] == "0.9999"
        assert float(eq.get("solref").split()[0]) == 2 * export.settings.timestep
    assert [p.name for p in tmp_path.iterdir()] == [export.path.name]  # no temp file left


def test_weld_for_6d_closures_and_rcm_sites(tmp_path):
    spherical = ET.parse(_export(rcm_pin.load("spherical_3rrr"), tmp_path)[0].path).getroot()
    assert len(list(spherical.iter("weld"))) == 2
    bevel = rcm_pin.load("rcm_bevel")
    root = ET.parse(_export(bevel, tmp_path)[0].path).getroot()
    sites = {s.get("name") for s in root.iter("site")}
    assert bevel.model.frames[bevel.rcm.point_frame_id].name in sites


def test_massless_bodies_get_the_floor_with_a_warning(tmp_path):
    mech = rcm_pin.load("rcm_two_mass")
    with pytest.warns(settings.InertiaFloorWarning, match="pair4"):
        export = to_mjcf(mech, tmp_path / "m.xml")
    assert "pair4" in export.floored
    check.load_mujoco(export.path, export.mechanism)


def test_kept_row_subsets_are_named(tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        export = to_mjcf(rcm_pin.load("eye_4dof"), tmp_path / "e.xml")
    named = [str(w.message) for w in caught if w.category is settings.InexactExportWarning]
    assert len(named) == 2 and len(export.inexact) == 2
    assert any("finger_K2-crank_K2" in m for m in named)
    assert any("link5_P-eye_2_P" in m for m in named)


def test_the_timestep_follows_the_tolerance(tmp_path):
    mech = rcm_pin.load("four_bar")
    loose = settings.choose(mech, drift_tol=1e-4)
    tight = settings.choose(mech, drift_tol=1e-8)
    assert tight.timestep < loose.timestep and tight.predicted_drift <= 1e-8
    assert tight.solref == (2 * tight.timestep, 1.0)
    user = settings.choose(mech, timestep=1e-4)
    assert user.timestep == 1e-4


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan")])
def test_bad_timestep_is_refused(tmp_path, bad):
    with pytest.raises(InvalidInputError, match="timestep"):
        to_mjcf(rcm_pin.load("four_bar"), tmp_path / "f.xml", timestep=bad)


def test_unwritable_paths_are_refused(tmp_path):
    mech = rcm_pin.load("four_bar")
    with pytest.raises(InvalidInputError, match="existing writable folder"):
        to_mjcf(mech, tmp_path / "missing" / "f.xml")
    with pytest.raises(InvalidInputError, match="existing writable folder"):
        to_mjcf(mech, tmp_path)


def test_unknown_name_is_a_typed_error():
    with pytest.raises(UnknownMechanismError):
        rcm_pin.load("no_such_mechanism")


def run(argv, blocked=()):
    code = textwrap.dedent(
        f"""
        import sys
        for name in {list(blocked)!r}:
            sys.modules[name] = None
        from rcm_pin.cli import main
        raise SystemExit(main({argv!r}))
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    return proc.returncode, proc.stdout, proc.stderr


def test_cli_writes_and_checks(tmp_path):
    out = tmp_path / "f.xml"
    code, stdout, err = run(["export", "five_bar", "--mjcf", str(out), "--check", "--json"])
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["mjcf"] == str(out) and out.is_file()
    assert doc["rigid_limit_error"] <= SOLVER
    assert doc["predicted_drift"] <= doc["drift_tol"]


def test_cli_bad_input(tmp_path):
    code, stdout, _ = run(["export", "nope", "--mjcf", str(tmp_path / "f.xml"), "--json"])
    assert code == 2 and json.loads(stdout)["error"]["type"] == "UnknownMechanismError"
    code, stdout, _ = run(["export", "four_bar", "--mjcf", str(tmp_path / "x" / "f.xml"), "--json"])
    assert code == 2 and json.loads(stdout)["error"]["type"] == "InvalidInputError"
    code, stdout, _ = run(["export", "four_bar", "--mjcf", "f.xml", "--timestep", "0", "--json"])
    assert code == 2 and json.loads(stdout)["error"]["type"] == "UsageError"


def test_without_mujoco_the_file_is_written_and_checking_names_the_extra(tmp_path, monkeypatch):
    out = tmp_path / "f.xml"
    code, stdout, _ = run(["export", "four_bar", "--mjcf", str(out), "--json"], ["mujoco"])
    assert code == 0 and out.is_file()
    code, stdout, _ = run(
        ["export", "four_bar", "--mjcf", str(out), "--check", "--json"], ["mujoco"]
    )
    assert code == 2
    error = json.loads(stdout)["error"]
    assert (
        error["type"] == "MissingExtraError" and "pip install 'rcm-pin[mujoco]'" in error["message"]
    )
    monkeypatch.setitem(sys.modules, "mujoco", None)
    mech = rcm_pin.load("four_bar")
    with pytest.raises(MissingExtraError, match=r"pip install 'rcm-pin\[mujoco\]'"):
        check.load_mujoco(to_mjcf(mech, out).path, mech)


def test_simulate_on_mujoco_follows_pinocchio_as_the_hold_shrinks():
    """The same law on the MuJoCo plant: the difference from the Pinocchio run is the
    zero-order hold's, first order in the control period; the closures stay within the
    export's drift tolerance."""
    from rcm_pin.control.scenario import run as run_scenario
    from rcm_pin.control.scenario import scenarios
    from rcm_pin.export.simulate import simulate_mujoco

    mech = rcm_pin.load("five_bar")
    sc = scenarios(mech)["crossing"]
    pin_run = run_scenario(mech, sc)
    coarse = simulate_mujoco(mech, sc, control_period=2e-3, compare=pin_run)
    fine = simulate_mujoco(mech, sc, control_period=5e-4, compare=pin_run)
    assert fine.max_difference < coarse.max_difference / 2
    assert coarse.max_equality_residual <= settings.DRIFT_TOL
    assert coarse.t[-1] == pytest.approx(sc.duration, abs=1e-12)


def test_cli_simulate_engine_mujoco():
    code, stdout, err = run(["simulate", "five_bar", "--engine", "mujoco", "--json"])
    assert code == 0, err
    mj = json.loads(stdout)["runs"][0]["mujoco"]
    assert mj["engine"] == "mujoco" and mj["max_equality_residual"] <= settings.DRIFT_TOL
    code, stdout, _ = run(["simulate", "five_bar", "--engine", "mujoco", "--json"], ["mujoco"])
    assert code == 2 and json.loads(stdout)["error"]["type"] == "MissingExtraError"


def test_a_mesh_outside_the_descriptions_folders_is_refused_as_by_view(tmp_path):
    """The export reads meshes through the viewer's policy: a URDF naming a file outside its
    folders is refused (an MJCF file makes MuJoCo read every mesh it names)."""
    from rcm_pin.errors import MeshLocationError

    secret = tmp_path / "private" / "secret.stl"
    secret.parent.mkdir()
    secret.write_bytes(b"solid x\nendsolid x\n")
    robot = tmp_path / "robot"
    robot.mkdir()
    (robot / "r.urdf").write_text(
        f'<robot name="r"><link name="a"><visual><geometry><mesh filename="{secret}"/>'
        '</geometry></visual><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" '
        'ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link><link name="b">'
        '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" '
        'izz="0.01"/></inertial></link><joint name="j" type="revolute"><parent link="a"/>'
        '<child link="b"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        "</robot>"
    )
    mech = rcm_pin.load(robot / "r.urdf", tool_frame="b")
    with pytest.raises(MeshLocationError, match=r"--mesh-dir PATH"):
        to_mjcf(mech, tmp_path / "r.xml")
    assert not (tmp_path / "r.xml").exists()
