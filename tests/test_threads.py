"""One Mechanism from 4 threads gives exactly the 1-thread results (issue 11, item 6).

Extends the thread-safety test of tests/test_loading.py (forward, the tool Jacobian and J̇)
to the analyses that keep scratch state in the per-thread Pinocchio ``Data``: velocity
(forward velocity, inverse velocity), tree dynamics (RNEA, CRBA, forward dynamics) and the
closed-loop solves (direct and inverse position problems of planar_3rrr and five_bar, the
velocity matrices A, B and the constrained forward dynamics). Equality is exact
(``np.testing.assert_array_equal``): the threads run the same floating-point operations.
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis import loop_velocity, velocity
from rcm_pin.dynamics import constrained, tree

N_THREADS = 4


def _in_threads(fn: Callable[[], list[Any]], n_threads: int = N_THREADS) -> list[list[Any]]:
    """fn() run by n_threads threads released together by a barrier."""
    results: list[Any] = [None] * n_threads
    errors: list[BaseException] = []
    barrier = threading.Barrier(n_threads)

    def run(i: int) -> None:
        barrier.wait()
        try:
            results[i] = fn()
        except BaseException as exc:  # re-raised in the main thread below
            errors.append(exc)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(n_threads)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert not any(t.is_alive() for t in threads), "a thread hangs"
    if errors:
        raise errors[0]
    return results


def _arrays(value: Any) -> list[np.ndarray]:
    """Every array of a result (dataclasses and tuples flattened), for exact comparison."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [a for f in dataclasses.fields(value) for a in _arrays(getattr(value, f.name))]
    if isinstance(value, (tuple, list)):
        return [a for v in value for a in _arrays(v)]
    return [np.asarray(value)]


def _same_in_threads(work: Callable[[], list[Any]]) -> None:
    reference = [_arrays(r) for r in work()]
    assert reference and all(reference)
    for result in _in_threads(work):
        assert len(result) == len(reference)
        for got, want in zip(result, reference, strict=True):
            got = _arrays(got)
            assert len(got) == len(want)
            for a, b in zip(got, want, strict=True):
                np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("name", ["rcm_bevel", "panda"])
def test_velocity_from_four_threads(name):
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(11)
    qs = rng.uniform(mech.lower, mech.upper, (60, mech.nq)) * 0.8
    qds, qdds = rng.normal(size=(2, 60, mech.nv))
    vs = rng.normal(size=(60, 3)) * 0.01

    def work():
        out = []
        for q, qd, qdd, v in zip(qs, qds, qdds, vs, strict=True):
            out.append(velocity.forward(mech, q, qd, qdd))
            out.append(velocity.inverse_velocity(mech, q, v))
        return out

    _same_in_threads(work)


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_two_mass", "ur5"])
def test_tree_dynamics_from_four_threads(name):
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(12)
    qs = rng.uniform(mech.lower, mech.upper, (60, mech.nq))
    vs, accs, taus = rng.normal(size=(3, 60, mech.nv))

    def work():
        out = []
        for q, v, a, tau in zip(qs, vs, accs, taus, strict=True):
            out.append(tree.inverse_dynamics(mech, q, v, a))
            out.append(tree.mass_matrix(mech, q))
            out.append(tree.forward_dynamics(mech, q, v, tau))
        return out

    _same_in_threads(work)


def _closed_configurations(mech: rcm_pin.Mechanism, n: int) -> list[np.ndarray]:
    home = mech.home
    drives = home[mech.loops.drive_q] + np.linspace(-0.05, 0.05, n)[:, None]
    return [rcm_pin.forward(mech, d, q_guess=home).solutions[0].q for d in drives]


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar"])
def test_closed_position_problems_from_four_threads(name):
    mech = rcm_pin.load(name)
    qs = _closed_configurations(mech, 15)
    drives = [q[mech.loops.drive_q] for q in qs]
    targets = [mech.output_value(mech.to_pin(q)) for q in qs]

    def work():
        out = []
        for d, t in zip(drives, targets, strict=True):
            fwd = rcm_pin.forward(mech, d, all_modes=True)
            inv = rcm_pin.inverse(mech, t)
            out.append([(s.q, s.output, s.residual) for s in fwd.solutions])
            out.append([(s.q, s.output, s.residual) for s in inv.solutions])
        return out

    _same_in_threads(work)


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar"])
def test_closed_velocity_and_dynamics_from_four_threads(name):
    mech = rcm_pin.load(name)
    qs = _closed_configurations(mech, 20)
    rng = np.random.default_rng(13)
    taus = rng.normal(size=(len(qs), mech.nv)) * 0.1

    def work():
        out = []
        for q, tau in zip(qs, taus, strict=True):
            out.append(loop_velocity.velocity_matrices(mech, q))
            out.append(constrained.forward_dynamics(mech, q, np.zeros(mech.nv), tau))
        return out

    _same_in_threads(work)
