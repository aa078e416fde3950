"""Natural frequencies with the drives as springs (paper 004): det(C − ω² M_q) = 0 beside the
finite-difference linearisation of the constrained forward dynamics, on all three parallel
mechanisms, and the ``rcm-pin vibrations`` command."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.loop_velocity import passive_velocity
from rcm_pin.analysis.position import forward
from rcm_pin.cli import main
from rcm_pin.dynamics.tree import mass_matrix_pin
from rcm_pin.dynamics.vibrations import (
    STIFFNESS_RANGE,
    linearised_frequencies,
    natural_frequencies,
    stiffness_vector,
    tangent_basis,
)
from rcm_pin.errors import InvalidInputError

NAMES = ("planar_3rrr", "spherical_3rrr", "translational_3ppapa")
#: Per-drive stiffness of each mechanism [N·m/rad, N·m/rad, N/m] (spread to split the modes).
STIFFNESS = {
    "planar_3rrr": (800.0, 1000.0, 1300.0),
    "spherical_3rrr": (150.0, 200.0, 260.0),
    "translational_3ppapa": (8e4, 1e5, 1.3e5),
}


@pytest.fixture(scope="module", params=NAMES)
def mech(request):
    return rcm_pin.load(request.param)


def random_poses(mech, n, seed):
    """n closed configurations near home: drives moved by up to ±0.05 (rad or m·L)."""
    rng = np.random.default_rng(seed)
    home = mech.home
    drives = mech.loops.drive_q
    scale = np.where(mech.revolute[drives], 0.05, 0.05 * mech.loops.length_scale)
    out = []
    for _ in range(n):
        qa = home[drives] + scale * rng.uniform(-1.0, 1.0, len(drives))
        out.append(forward(mech, qa, q_guess=home).solutions[0].q)
    return out


def test_two_routes_agree_on_random_poses(mech):
    # acceptance: 1e-6 relative (the central differences reach ~1e-10)
    for q in random_poses(mech, 3, seed=14):
        c = STIFFNESS[mech.name]
        vib = natural_frequencies(mech, q, c)
        lin = linearised_frequencies(mech, q, c)
        np.testing.assert_allclose(lin, vib.frequencies, rtol=1e-6)
        assert np.all(np.diff(vib.frequencies) >= 0)


def test_frequency_equation_and_mode_normalisation(mech):
    q = random_poses(mech, 1, seed=3)[0]
    vib = natural_frequencies(mech, q, STIFFNESS[mech.name])
    c = np.diag(vib.stiffness)
    for j, w in enumerate(vib.frequencies):
        assert abs(np.linalg.det(c - w**2 * vib.mass)) < 1e-9 * np.linalg.det(c)
        np.testing.assert_allclose(
            c @ vib.modes[:, j],
            w**2 * vib.mass @ vib.modes[:, j],
            rtol=1e-10,
            atol=1e-10 * np.max(np.abs(c)),
        )
    np.testing.assert_allclose(vib.modes.T @ vib.mass @ vib.modes, np.eye(3), atol=1e-10)


def test_frequencies_scale_as_sqrt_c(mech):
    q = random_poses(mech, 1, seed=5)[0]
    base = natural_frequencies(mech, q, STIFFNESS[mech.name]).frequencies
    for k in (0.01, 4.0, 100.0):
        scaled = natural_frequencies(mech, q, k * np.array(STIFFNESS[mech.name])).frequencies
        np.testing.assert_allclose(scaled, np.sqrt(k) * base, rtol=1e-12)


def test_tangent_basis_and_reduced_mass_by_kinetic_energy(mech):
    q = random_poses(mech, 1, seed=7)[0]
    s = tangent_basis(mech, q)
    jc = mech.constraint_jacobian(q)
    np.testing.assert_allclose(jc @ s, 0.0, atol=1e-12)
    vib = natural_frequencies(mech, q, 1.0)
    rng = np.random.default_rng(11)
    m_full = mass_matrix_pin(mech.model, mech.data, q)
    for _ in range(3):
        qd_a = rng.normal(size=3)
        v = passive_velocity(mech, q, qd_a)  # second route: the loop-velocity module
        np.testing.assert_allclose(qd_a @ vib.mass @ qd_a, v @ m_full @ v, rtol=1e-10)


def test_stiffness_errors():
    mech = rcm_pin.load("planar_3rrr")
    with pytest.raises(InvalidInputError) as e:
        stiffness_vector(mech, [1.0, 2.0])
    assert str(e.value) == "stiffness has 2 values; valid: 1 or 3 (one per drive of planar_3rrr)"
    with pytest.raises(InvalidInputError) as e:
        stiffness_vector(mech, [1.0, -2.0, 3.0])
    assert str(e.value) == (
        "stiffness [1.0, -2.0, 3.0] is outside the valid range; valid: 0.001 to 1e+10 "
        "[N·m/rad, N/m] (above, the spring efforts of the linearisation step exceed the 1e6 "
        "effort bound; below, the modes are too slow to separate from the closure stabilisation)"
    )


def _json(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_cli_keys_default_mode_and_check(capsys):
    code, out = _json(
        capsys,
        ["vibrations", "planar_3rrr", "--pose", "0.02,0.01,0.1", "--stiffness", "1000", "--check"],
    )
    assert code == 0 and out["drives"] == ["A1", "A2", "A3"] and out["mode"] == "+++"
    _, ik = _json(capsys, ["ik", "planar_3rrr", "--pose", "0.02,0.01,0.1"])
    assert ik["solutions"][0]["mode"] == out["mode"]
    vib = natural_frequencies(rcm_pin.load("planar_3rrr"), ik["solutions"][0]["q"], 1000.0)
    np.testing.assert_allclose(out["frequencies"], vib.frequencies, rtol=1e-12)
    np.testing.assert_allclose(np.array(out["modes"]).T, vib.modes, rtol=1e-12, atol=1e-12)
    assert out["max_relative_difference"] < 1e-6


def test_cli_rotation_output_and_errors(capsys):
    code, out = _json(
        capsys,
        [
            "vibrations",
            "spherical_3rrr",
            "--rpy",
            "0.1,0.2,0.05",
            "--stiffness",
            "100,200,300",
            "--mode",
            "+-+",
        ],
    )
    assert code == 0 and out["mode"] == "+-+" and len(out["frequencies"]) == 3
    code, out = _json(
        capsys,
        [
            "vibrations",
            "planar_3rrr",
            "--pose",
            "0.02,0.01,0.1",
            "--stiffness",
            "1",
            "--mode",
            "xyz",
        ],
    )
    assert code == 2 and out["error"]["type"] == "InvalidInputError"
    assert out["error"]["message"].startswith("mode 'xyz' is not a working mode of planar_3rrr")
    code, out = _json(capsys, ["vibrations", "rcm_bevel", "--pose", "0", "--stiffness", "1"])
    assert code == 2
    assert out["error"]["message"] == (
        "vibrations needs a closed mechanism (drives as springs); rcm_bevel is serial"
    )


@pytest.mark.parametrize("check", [[], ["--check"]])
@pytest.mark.parametrize("c", ["1e300", "1e11", "1e-4", "1,1e300,1"])
def test_cli_stiffness_out_of_range_exits_2(capsys, check, c):
    argv = ["vibrations", "planar_3rrr", "--pose", "0.02,0.01,0.1", f"--stiffness={c}", *check]
    code, out = _json(capsys, argv)
    assert code == 2 and out["error"]["type"] == "InvalidInputError"
    assert (
        "is outside the valid range; valid: 0.001 to 1e+10 [N·m/rad, N/m]"
        in (out["error"]["message"])
    )


def test_the_ends_of_the_stiffness_range_pass_both_routes():
    mech = rcm_pin.load("planar_3rrr")
    q = random_poses(mech, 1, 3)[0]
    for c in STIFFNESS_RANGE:
        w = natural_frequencies(mech, q, c).frequencies
        np.testing.assert_allclose(linearised_frequencies(mech, q, c), w, rtol=1e-3)


def test_type2_pose_has_no_spring_frequencies():
    from rcm_pin.errors import SingularConfigurationError
    from rcm_pin.studies.vibration_criterion import setups
    from rcm_pin.studies.working_mode import configuration_at

    p = setups()[0]
    mech = rcm_pin.load(p.name)
    q = configuration_at(mech, p.singular, p.mode)[0]
    with pytest.raises(SingularConfigurationError) as e:
        natural_frequencies(mech, q, 1.0)
    assert str(e.value) == (
        f"{p.name}: the passive closure Jacobian is singular (type-2 singularity): the drives "
        "as springs do not hold the output; valid: a regular pose"
    )


def test_criterion_drop_and_law():
    from rcm_pin.studies.vibration_criterion import approach, passive_det, setups

    for p in setups():
        r = approach(p)
        # "tens to hundreds of times": ω₁ ∝ d, so the drop is ~1/f (measured 5.8..9.5, 59..95,
        # 588..1051 for f = 1e-1, 1e-2, 1e-3)
        assert 3.0 < r["drop"]["0.1"] < 30.0 and 30.0 < r["drop"]["0.01"] < 300.0
        assert 300.0 < r["drop"]["0.001"] < 3000.0
        assert abs(r["slope_sigma"] - 1.0) < 0.1 and abs(r["slope_distance"] - 1.0) < 0.15
        if not r["crossing"]:  # the Agile Eye: x* is on its type 1+2 set (family's route)
            assert p.name == "spherical_3rrr" and r["rows"][-1]["sigma_min_A"] < 2e-3
            continue
        mech = rcm_pin.load(p.name)
        from rcm_pin.studies.working_mode import configuration_at

        q_star = configuration_at(mech, p.pose(r["s_star"]), p.mode)[0]
        q_start = configuration_at(mech, p.pose(1.0), p.mode)[0]
        assert abs(passive_det(mech, q_star)) < 1e-6 * abs(passive_det(mech, q_start))


def test_frequency_map_matches_pointwise():
    from rcm_pin.studies.vibration_criterion import frequency_map
    from rcm_pin.studies.working_mode import configuration_at

    u = np.array([-0.05, 0.0, 0.05])
    w = frequency_map("planar_3rrr", "+++", lambda x, y: np.array([x, y, 0.0]), u, u[:2], 1e3)
    mech = rcm_pin.load("planar_3rrr")
    q = configuration_at(mech, np.array([0.05, 0.0, 0.0]), "+++")[0]
    assert w.shape == (2, 3)
    assert w[1, 2] == natural_frequencies(mech, q, 1e3).frequencies[0]


def test_cli_type2_pose_exits_2(capsys):
    from rcm_pin.studies.vibration_criterion import setups

    p = setups()[0]
    pose = ",".join(repr(float(v)) for v in p.singular)
    code, out = _json(
        capsys, ["vibrations", p.name, f"--pose={pose}", "--mode", p.mode, "--stiffness", "1"]
    )
    assert code == 2 and out["error"]["type"] == "SingularConfigurationError"


def test_over_constrained_loops_frequency_route_and_refused_linearisation():
    """The 4R-parallelogram model: M_q on the independent closure rows gives the mimic
    model's frequencies (same geometry and masses: 1e-9); the KKT route is refused."""
    loops = rcm_pin.load("translational_3ppapa_loops")
    mimic = rcm_pin.load("translational_3ppapa")
    from rcm_pin.studies.working_mode import configuration_at

    pose = np.array([0.05, 0.0, 0.0])
    w_l = natural_frequencies(loops, configuration_at(loops, pose, "++/++/++")[0], 1e5)
    w_m = natural_frequencies(mimic, configuration_at(mimic, pose, "++/++/++")[0], 1e5)
    np.testing.assert_allclose(w_l.frequencies, w_m.frequencies, rtol=1e-9)
    with pytest.raises(InvalidInputError, match="closure rows are dependent"):
        linearised_frequencies(loops, w_l.q, 1e5)
