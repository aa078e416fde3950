"""One rule for named configurations: ``mech.home`` / ``mech.configurations``."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin.model.configurations import default_home, mid_range

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"


def test_family_home_is_mech_home():
    for name in ("rcm_bevel", "four_bar", "planar_3rrr"):
        mech = rcm_pin.load(name)
        named = mech.family.configurations(mech)
        assert np.array_equal(mech.home, named["home"]), name
        assert set(mech.configurations) == set(named)


def test_default_home_serial_is_mid_range_zero_for_unbounded():
    mech = rcm_pin.load(DATA / "mimic_tree.urdf", tool_frame="tool_link")
    bounded = np.isfinite(mech.lower)  # the continuous joint "cont": unbounded, home 0
    assert bounded.tolist().count(False) == 1
    expected = np.zeros(mech.nq)
    expected[bounded] = 0.5 * (mech.lower[bounded] + mech.upper[bounded])
    assert np.array_equal(mech.home, expected)
    assert list(mech.configurations) == ["home"]
    lower, upper = mech.lower.copy(), mech.upper.copy()
    lower[0], upper[0], lower[1] = -np.inf, np.inf, 0.2
    upper[1] = np.inf
    from dataclasses import replace

    q = mid_range(replace(mech, lower=lower, upper=upper))
    assert q[0] == 0.0 and q[1] == 0.2  # unbounded: 0; half-bounded: 0 clipped into range


def test_default_home_closed_is_assembled():
    m4 = rcm_pin.load("four_bar")
    from dataclasses import replace

    from rcm_pin.model.family import Family

    bare = replace(m4, family=Family())
    home = bare.home
    assert np.array_equal(home, default_home(bare))
    assert np.linalg.norm(bare.closure_residual(home)) < 1e-9
    assert np.allclose(home[bare.loops.drive_q], mid_range(bare)[bare.loops.drive_q])


def test_home_is_a_copy():
    mech = rcm_pin.load("rcm_bevel")
    mech.home[:] = 99.0
    mech.configurations["home"][:] = 99.0
    assert not np.any(mech.home == 99.0)


@pytest.mark.parametrize("key", ["mid", "regular"])
def test_no_magic_configuration_keys_in_generic_code(key):
    generic = ["rcm_pin/analysis", "rcm_pin/control", "rcm_pin/viz", "rcm_pin/cli", "ocp"]
    out = subprocess.run(
        ["grep", "-rn", f'"{key}"', *generic, ".ci/wheel_smoke.py"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    ).stdout
    hits = [h for h in out.splitlines() if re.search(rf'(get\(|\[)"{key}"', h)]
    assert hits == []


def grep(*pattern: str) -> str:
    """``grep -rn`` over the package sources (empty: no hit)."""
    argv = ["grep", "-rn", "--include=*.py", *pattern, "rcm_pin", "ocp"]
    return subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, check=False).stdout


def test_require_loops_is_public():
    assert grep("_require_loops") == ""
    with pytest.raises(rcm_pin.errors.InvalidInputError):
        rcm_pin.load("rcm_bevel").require_loops()


def test_no_private_controller_state_is_read_across_modules():
    """The hot paths and simulate use the controller's public posture, task_error and
    hot_path_law (issue 24, item 4), never its private names."""
    assert grep("-E", r"\._posture|\._task_error|_hot_path\(\)") == ""
