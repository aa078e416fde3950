"""Shared fixtures: loaded mechanisms (cached per session) and tolerances."""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
if "RCM_PIN_CACHE" not in os.environ:
    # compiled CasADi kernels (ocp.compiled) go to a cache of this session, never the
    # user's: every run pays the cold compiles CI pays, and leaves nothing behind
    _CACHE = tempfile.mkdtemp(prefix="rcm_pin_test_cache_")
    os.environ["RCM_PIN_CACHE"] = _CACHE
    atexit.register(shutil.rmtree, _CACHE, ignore_errors=True)

#: Identities of exact formulas (closed form vs Pinocchio, coupling projections).
EXACT = 1e-12
#: Results of iterative solvers.
SOLVER = 1e-9

RCM_NAMES = ("rcm_bevel", "rcm_bevel_4dof", "rcm_belt")


@pytest.fixture(scope="session", params=RCM_NAMES)
def rcm_mech(request):
    """Each shipped serial RCM mechanism with default arguments."""
    import rcm_pin

    return rcm_pin.load(request.param)


def closed_cases(mech, rng, n, spread, drive_spread=0.2):
    """n (drives, start) pairs of a closed mechanism: drives uniform within
    ``drive_spread`` of home's, starts home plus normal noise of deviation ``spread``."""
    loops, home = mech.loops, mech.home
    drives = home[loops.drive_q] + rng.uniform(-drive_spread, drive_spread, (n, loops.dof))
    return [(d, home + rng.normal(0.0, spread, mech.nq)) for d in drives]


def random_q(mech, n, rng, margin=0.0):
    """n random configurations within the joint limits (shrunk by ``margin``)."""
    lo, hi = mech.lower + margin, mech.upper - margin
    return rng.uniform(lo, hi, size=(n, mech.nq))


@pytest.fixture(scope="session")
def m3():
    """The planar 3-RRR closed mechanism with default arguments."""
    import rcm_pin

    return rcm_pin.load("planar_3rrr")


@pytest.fixture(scope="session")
def m5():
    """The five-bar closed mechanism with default arguments."""
    import rcm_pin

    return rcm_pin.load("five_bar")


@pytest.fixture(autouse=True)
def _seed_pinocchio():
    """Seed Pinocchio's own generator (pin.randomConfiguration) so every test is repeatable."""
    import pinocchio as pin

    pin.seed(0)
