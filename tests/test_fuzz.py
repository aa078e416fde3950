"""Fuzz suite, bounded profile (issue 11): bad input never crashes, every result is checked.

Hypothesis strategies over every catalogue mechanism (:func:`rcm_pin.names`) for ``load``
arguments, :func:`rcm_pin.forward` / :func:`rcm_pin.inverse` / :func:`rcm_pin.tool_pose`
inputs and the CLI ``fk`` / ``ik`` / ``singularities`` / ``workspace`` arguments (and
``fourbar``, ``vibrations --stiffness``, ``simulate --duration``, ``ocp track --n``: the
ranges and cost bounds of issue 26): numbers of
every magnitude (1e300, -0.0, subnormals, NaN, inf), wrong lengths, strings, nested lists,
non-rotations, poses far outside the workspace. Property (the ``check_*`` functions): either
a valid result that a second route confirms, or an :class:`~rcm_pin.errors.RcmPinError`
(CLI: exit 2 or 3 with the JSON error document); never another exception, never a warning
(warnings are errors inside every check), never a hang (hypothesis ``deadline``).

Second routes: forward kinematics of a fresh Pinocchio ``Data`` (``framesForwardKinematics``)
for every output value (1e-12); FK of an IK solution meets the target (1e-9); a closed-loop
solution has closure residual <= 1e-12, its drives equal the given drives (1e-12) and its
output equals the target (1e-9). ``benchmarks/fuzz_long.py`` runs the same checks >= 1e4
times per entry point.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin import errors
from rcm_pin.cli import main as cli_main
from rcm_pin.errors import RcmPinError
from rcm_pin.model.render import declared_args

EXACT = 1e-12  # closed forms and FK against FK [m, rad]
SOLVER = 1e-9  # solvers against their target [m, rad]
NAMES = rcm_pin.names()
MECHS = {n: rcm_pin.load(n) for n in NAMES}
SPECIAL = [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-300, 1e6, -1e6, 1e6 + 1]
SPECIAL += [1e20, -1e20, 1e154, 1e300, -1e300, 1.7976931348623157e308, math.nan, math.inf]
SPECIAL += [-math.inf]
BOUNDED = settings(
    max_examples=8,
    deadline=5000,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


# ---------------------------------------------------------------------------- strategies
def numbers() -> st.SearchStrategy[Any]:
    """Floats and integers of every magnitude, the special values included."""
    return st.one_of(
        st.sampled_from(SPECIAL),
        st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
        st.floats(-10.0, 10.0),
        st.integers(-(10**30), 10**30),
    )


def junk() -> st.SearchStrategy[Any]:
    """Things that are no numeric vector at all."""
    return st.one_of(
        st.none(),
        st.text(max_size=6),
        st.binary(max_size=4),
        st.just([[1.0, 2.0], [3.0]]),
        st.just({"a": 1}),
        st.just([1j, 2.0]),
        st.lists(st.sampled_from(["1", "x", "nan", ""]), min_size=1, max_size=6),
        st.lists(st.lists(numbers(), max_size=3), min_size=1, max_size=4),
    )


def in_box(lo: np.ndarray, hi: np.ndarray) -> st.SearchStrategy[np.ndarray]:
    """Uniform points of the box [lo, hi] (finite bounds)."""
    u = st.lists(st.floats(0.0, 1.0), min_size=len(lo), max_size=len(lo))
    return u.map(lambda v: lo + (hi - lo) * np.array(v))


def mech_inputs(mech: rcm_pin.Mechanism) -> st.SearchStrategy[Any]:
    """What :func:`rcm_pin.forward` takes, right and wrong."""
    n = len(mech.input_names)
    if mech.loops is None:
        lo, hi = mech.lower, mech.upper
    else:
        home = mech.home[mech.loops.drive_q]
        lo, hi = home - 0.3, home + 0.3
    return st.one_of(
        in_box(lo, hi),
        in_box(lo, hi),
        st.lists(numbers(), min_size=n, max_size=n),
        st.lists(numbers(), max_size=n + 2),
        in_box(lo, hi).map(lambda q: (q * 1e3).tolist()),
        junk(),
    )


def mech_targets(mech: rcm_pin.Mechanism) -> st.SearchStrategy[Any]:
    """What :func:`rcm_pin.inverse` takes: reachable, perturbed, far, non-rotations, junk."""
    reach = mech_inputs(mech).filter(lambda q: isinstance(q, np.ndarray))

    def value(q: np.ndarray) -> Any:
        try:
            return rcm_pin.forward(mech, q).solutions[0].output
        except RcmPinError:
            return np.zeros(mech.output.size)

    size = mech.output.size
    out = [
        reach.map(value),
        reach.map(value),
        st.tuples(reach.map(value), st.floats(-0.05, 0.05)).map(lambda t: t[0] + t[1]),
        reach.map(lambda q: value(q) * 1e4),
        st.lists(numbers(), min_size=size, max_size=size),
        st.lists(numbers(), max_size=size + 3),
        junk(),
    ]
    if mech.output.coords[-1] == "rotation" and mech.loops is None:
        out.append(reach.map(lambda q: rcm_pin.tool_pose(mech, q)))
        out.append(st.lists(st.floats(-2, 2), min_size=16, max_size=16).map(_matrix4))
    return st.one_of(out)


def _matrix4(values: list[float]) -> np.ndarray:
    return np.reshape(values, (4, 4))


# ---------------------------------------------------------------------------- second routes
def fresh_value(mech: rcm_pin.Mechanism, q: np.ndarray, output: Any = None) -> np.ndarray:
    """Output value at coordinates q from a fresh Pinocchio Data (the second route)."""
    data = mech.model.createData()
    pin.framesForwardKinematics(mech.model, data, mech.to_pin(q))
    out = mech.output if output is None else output
    return out.value(pin.SE3(data.oMf[out.frame_id]))


def _closure_ok(mech: rcm_pin.Mechanism, q: np.ndarray) -> None:
    res = float(np.max(np.abs(mech.closure_residual(mech.to_pin(q))), initial=0.0))
    assert res <= EXACT, f"closure residual {res:.3g} > {EXACT}"


def check_forward(mech: rcm_pin.Mechanism, x: Any) -> str:
    """``valid`` (confirmed) or ``typed``; anything else raises."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            result = rcm_pin.forward(mech, x)
        except RcmPinError:
            return "typed"
        for sol in result.solutions:
            np.testing.assert_allclose(sol.output, fresh_value(mech, sol.q), atol=EXACT, rtol=0)
            given_inputs = np.asarray(x, dtype=float)
            np.testing.assert_allclose(result.inputs(sol), given_inputs, atol=EXACT, rtol=0)
            if mech.loops is not None:
                _closure_ok(mech, sol.q)
    return "valid"


def check_tool_pose(mech: rcm_pin.Mechanism, x: Any) -> str:
    """tool_pose / frame_pose against a fresh Data, or a typed error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            T = rcm_pin.tool_pose(mech, x)
        except RcmPinError:
            return "typed"
        data = mech.model.createData()
        pin.framesForwardKinematics(mech.model, data, mech.to_pin(np.asarray(x, dtype=float)))
        np.testing.assert_allclose(T, data.oMf[mech.tool_frame_id].homogeneous, atol=EXACT)
    return "valid"


def check_inverse(mech: rcm_pin.Mechanism, target: Any, coords: Any = None) -> str:
    """Every solution reaches the target in fresh FK (closed: closure and output)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            result = rcm_pin.inverse(mech, target, coords)
        except RcmPinError:
            return "typed"
        for sol in result.solutions:
            value = fresh_value(mech, sol.q, result.output)
            err = float(np.max(np.abs(result.output.error(value, result.given)), initial=0.0))
            assert err <= SOLVER, f"{mech.name}: FK misses the target by {err:.3g}"
            if mech.loops is not None:
                _closure_ok(mech, sol.q)
    return "valid"


def check_load(name: Any, args: dict[str, Any]) -> str:
    """load gives a Mechanism whose FK runs, or a typed error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            mech = rcm_pin.load(name, **args)
        except RcmPinError:
            return "typed"
        assert isinstance(mech, rcm_pin.Mechanism)
    return "valid"


ERROR_TYPES = set(errors.__all__) | {"UsageError"}


def check_cli(argv: list[str]) -> str:
    """Exit 0 with a JSON document (fk / ik: checked by fresh FK), or 2 / 3 with the error."""
    out, err = io.StringIO(), io.StringIO()
    with (
        warnings.catch_warnings(),
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        warnings.simplefilter("error")
        rc = cli_main(argv)
    text = out.getvalue()
    if rc in (2, 3):
        doc = json.loads(text)
        assert set(doc) == {"error"} and doc["error"]["type"] in ERROR_TYPES, text[:300]
        assert doc["error"]["message"] and "\n" not in doc["error"]["message"]
        return "typed"
    assert rc == 0, f"exit {rc}: {err.getvalue()[-500:]}"
    doc = json.loads(text)
    if argv[0] in ("fk", "ik"):
        mech = MECHS[argv[1]]
        for sol in doc["solutions"]:
            q = np.array(sol["q"])
            got = mech.output.to_json(fresh_value(mech, q))
            for key in ("x", "y", "z", "rz"):
                if key in sol["output"]:
                    assert abs(got[key] - sol["output"][key]) <= EXACT
            if mech.loops is not None:
                _closure_ok(mech, q)
    return "valid"


# ---------------------------------------------------------------------------- CLI argv
def _text(values: Any) -> str:
    if isinstance(values, (np.ndarray, list)):
        flat = np.asarray(values, dtype=object).ravel().tolist() if len(values) else []
        return ",".join(repr(float(v)) if isinstance(v, (int, float)) else str(v) for v in flat)
    return str(values)


def _rows(target: Any) -> str:
    if isinstance(target, np.ndarray) and target.ndim == 2:
        return ";".join(_text(r) for r in target[:3])
    return _text(target)


def cli_argv(name: str, command: str | None = None) -> st.SearchStrategy[list[str]]:
    """fk / ik / singularities / workspace command lines of one mechanism (or one command)."""
    mech = MECHS[name]
    q = mech_inputs(mech).filter(lambda v: not isinstance(v, (dict, bytes)))
    q_text = st.one_of(q.map(_text), st.text(max_size=8))
    xyz = st.one_of(
        st.lists(st.floats(-0.3, 0.3), min_size=3, max_size=3).map(_text),
        st.lists(numbers(), min_size=3, max_size=3).map(_text),
        st.text(max_size=6),
    )
    rpy = st.lists(numbers(), min_size=3, max_size=3).map(_text)
    pose = mech_targets(mech).map(_rows)
    base = ["--json"]
    ints = st.one_of(st.integers(-5, 50), st.sampled_from([0, 10**6, 10**12]))
    # workspace: valid sample counts kept small (each valid run costs ~0.1 s)
    samples = st.one_of(
        st.integers(1000, 1500).map(str), st.integers().map(str), numbers().map(repr)
    ).map(lambda v: ["--samples", v])
    grid = st.one_of(st.integers(-3, 9).map(str), st.integers().map(str), st.text(max_size=3))
    grid = grid.map(lambda v: ["--n", v])  # the defaults (2e5 samples, 121²) take seconds
    grid = grid if mech.loops is not None else st.one_of(grid, st.just([]))
    extra = st.one_of(
        st.just([]),
        numbers().map(lambda v: [f"--phi={v!r}"]),
        st.lists(numbers(), min_size=1, max_size=3).map(lambda v: [f"--phi-range={_text(v)}"]),
    )
    by_command = {
        "fk": [
            q_text.map(lambda s: ["fk", name, "--q", s, *base]),
            q_text.map(lambda s: ["fk", name, f"--q={s}", "--all", *base]),
        ],
        "ik": [
            xyz.map(lambda s: ["ik", name, "--xyz", s, *base]),
            st.tuples(xyz, rpy).map(lambda t: ["ik", name, "--xyz", t[0], "--rpy", t[1], *base]),
            pose.map(lambda s: ["ik", name, "--pose", s, *base]),
        ],
        "singularities": [
            q_text.map(lambda s: ["singularities", name, "--q", s, *base]),
            st.tuples(ints, ints).map(
                lambda t: ["singularities", name, "--grid", f"1,2,{t[0]}", "--n", str(t[1]), *base]
            ),
        ],
        "workspace": [
            st.tuples(samples, grid, extra).map(
                lambda t: ["workspace", name, *t[0], *t[1], *t[2], *base]
            ),
        ],
    }
    chosen = list(by_command) if command is None else [command]
    return st.one_of([s for c in chosen for s in by_command[c]])


# ---------------------------------------------------------------------------- load arguments
XACRO = {n: declared_args(m.source) for n, m in MECHS.items() if m.source is not None}


def load_args() -> st.SearchStrategy[tuple[Any, dict[str, Any]]]:
    """Names, paths and xacro arguments of every type and magnitude."""
    value = st.one_of(numbers(), st.text(max_size=5), st.booleans(), st.none(), st.just([1]))
    xacro = st.sampled_from(sorted(XACRO)).flatmap(
        lambda n: st.tuples(
            st.just(n), st.dictionaries(st.sampled_from(sorted(XACRO[n])), value, max_size=2)
        )
    )
    paths = st.sampled_from(["", "   ", "/nonexistent/x.urdf", "/tmp", "x.xacro", ".urdf"])
    bad = st.one_of(paths, st.none(), st.integers(), st.text(max_size=8), st.just(Path("/")))
    return st.one_of(
        xacro,
        st.tuples(bad, st.just({})),
        st.tuples(st.sampled_from(NAMES), st.dictionaries(st.text(max_size=4), value, max_size=1)),
    )


# ---------------------------------------------------------------------------- the properties
pytestmark = pytest.mark.filterwarnings("error")


def _examples(mech: rcm_pin.Mechanism) -> int:
    """Examples per mechanism in the bounded profile: fewer where one solve is slow (the
    arms' multistart least squares, closed mechanisms of many joints)."""
    return 3 if mech.family.name == "arm" or mech.nq > 8 else 8


def _fuzz(mech: rcm_pin.Mechanism, body: Any) -> None:
    settings(BOUNDED, max_examples=_examples(mech))(given(data=st.data())(body))()


@pytest.mark.parametrize("name", NAMES)
def test_forward_and_tool_pose_fuzz(name):
    mech = MECHS[name]

    def body(data: Any) -> None:
        x = data.draw(mech_inputs(mech))
        assert check_forward(mech, x) in ("valid", "typed")
        if mech.loops is None:
            assert check_tool_pose(mech, x) in ("valid", "typed")

    _fuzz(mech, body)


@pytest.mark.parametrize("name", NAMES)
def test_inverse_fuzz(name):
    mech = MECHS[name]

    def body(data: Any) -> None:
        assert check_inverse(mech, data.draw(mech_targets(mech))) in ("valid", "typed")
        if mech.output.coords[:3] == ("x", "y", "z"):
            xyz = data.draw(st.lists(numbers(), min_size=3, max_size=3))
            assert check_inverse(mech, xyz, ("x", "y", "z")) in ("valid", "typed")

    _fuzz(mech, body)


@settings(BOUNDED, max_examples=30)
@given(case=load_args())
def test_load_fuzz(case):
    assert check_load(*case) in ("valid", "typed")


@pytest.mark.parametrize("name", NAMES)
def test_cli_fuzz(name):
    def body(data: Any) -> None:
        assert check_cli(data.draw(cli_argv(name))) in ("valid", "typed")

    _fuzz(MECHS[name], body)


def test_the_listed_cases_give_typed_errors(tmp_path):
    mech = MECHS["rcm_bevel"]
    for bad in ("", None, str(tmp_path / "missing.urdf"), str(tmp_path)):
        with pytest.raises(RcmPinError):
            rcm_pin.load(bad)
    (tmp_path / "bad.urdf").write_text("<robot name='x'><link")
    with pytest.raises(errors.InvalidInputError, match="not well-formed XML"):
        rcm_pin.load(tmp_path / "bad.urdf")
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.tool_pose(mech, "abc")
    assert str(exc.value) == "q 'abc' is not numeric; valid: real numbers"
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.forward(mech, [1e300, 0, 0, 0, 0, 0])
    assert str(exc.value) == (
        "q has an entry of magnitude 1e+300; valid: |value| <= 1e+06 (larger values are "
        "meaningless for a mechanism)"
    )
    with pytest.raises(
        errors.InvalidInputError, match=r"^target has an entry of magnitude 1e\+300"
    ):
        rcm_pin.inverse(mech, [1e300, 0, 0], ("x", "y", "z"))
    with pytest.raises(errors.InvalidInputError, match="is not numeric"):
        rcm_pin.forward(mech, ["1"] * 6)
    assert check_cli(["ik", "rcm_bevel", "--xyz=0,0,-0.1", "--rpy=1e20,0,0", "--json"]) == "typed"


def test_messages_of_the_fixed_inputs():
    """Typed errors with short one-line messages (no np.int64, no whole inputs)."""
    mech = MECHS["rcm_bevel"]
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.inverse(mech, [0.01, 0.01, -0.1], 5)
    assert str(exc.value) == (
        "coords 5 is not a sequence of output coordinates; valid: a tuple of tokens from x, "
        "y, z, rotation, e.g. ('x', 'y', 'z')"
    )
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.tool_poses(mech, np.zeros((2, 6, 6)))
    assert str(exc.value) == "configurations have shape (2, 6, 6); valid: (N, 6) finite values"
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.forward(mech, np.zeros(6) + 0j)
    assert str(exc.value) == (
        "q array([0.+0.j, 0.+0.j, 0.+0.j, 0.+0.j, 0.+0.j, 0.+0.j]) is not numeric; valid: "
        "real numbers"
    )
    with pytest.raises(errors.InvalidInputError, match=r"^q \[1000000000000000000000000"):
        rcm_pin.forward(mech, [10**400, 0, 0, 0, 0, 0])
    with pytest.raises(errors.NotARotationError) as exc:
        rcm_pin.rotations.project_to_rotation(np.stack([np.eye(3), 2 * np.eye(3)]))
    assert str(exc.value) == (
        "matrix is not a rotation: distance to the nearest rotation 1.73 at index (1,) exceeds "
        "the tolerance 0.01 (Frobenius norm ||R - R_proj||)"
    )
    with pytest.raises(errors.NotARotationError, match="an entry of magnitude 1e"):
        rcm_pin.rotations.project_to_rotation(np.full((3, 3), 1e200))
    with pytest.raises(errors.InvalidInputError, match=r"^target has an entry of magnitude"):
        rcm_pin.inverse(mech, np.r_[0.0, 0.0, -0.1, np.full(9, 1e200)])
    with pytest.raises(errors.InvalidInputError, match="is not numeric"):
        rcm_pin.inverse(mech, np.full((4, 4), "a"))


# ------------------------------------------------ bounds and ranges (issue 26, item 7)
def _flag(option: str, values: st.SearchStrategy[Any]) -> st.SearchStrategy[str]:
    return values.map(lambda v: f"{option}={v!r}")


def fourbar_argv() -> st.SearchStrategy[list[str]]:
    """fourbar synthesize / analyse: lengths and angles of every magnitude, and swings that
    have crank-rocker solutions (up, down 15-35 deg, coupler 0.07-0.09 m, rocker 0.05 m)."""
    wild = [_flag(f"--{k}", numbers()) for k in ("up", "down", "coupler", "rocker")]
    swing = st.floats(15.0, 35.0)
    coupler, rocker = _flag("--coupler", st.floats(0.07, 0.09)), _flag("--rocker", st.just(0.05))
    sane = [_flag("--up", swing), _flag("--down", swing), coupler, rocker]
    mixed = [st.one_of(a, b) for a, b in zip(sane, wild, strict=True)]
    lengths = st.one_of(numbers(), st.floats(0.04, 0.12))
    analyse = st.tuples(*(_flag(f"--{k}", lengths) for k in ("frame", "crank", "coupler",
                                                             "rocker")))  # fmt: skip
    return st.one_of(
        st.tuples(*sane).map(lambda t: ["fourbar", "synthesize", *t, "--json"]),
        st.tuples(*mixed).map(lambda t: ["fourbar", "synthesize", *t, "--json"]),
        analyse.map(lambda t: ["fourbar", "analyse", *t, "--json"]),
    )


def _runs_long(v: Any) -> bool:
    """A duration that the budget lets run past 0.05 s (a positive integer included)."""
    return (isinstance(v, float) and 0.05 < v < 1e5) or (isinstance(v, int) and v > 0)


def bounds_argv() -> st.SearchStrategy[list[str]]:
    """vibrations --stiffness, simulate --duration / --gains / --tau-zeta and ocp track --n
    of every magnitude. The
    durations a budget allows past 0.05 s and the grids up to the memory bound are left
    out: each is a real run of seconds to minutes (the bound is what is fuzzed)."""
    stiffness = st.one_of(
        st.floats(1.0, 1e4), numbers(), st.lists(numbers(), min_size=1, max_size=4)
    )
    vib = st.tuples(stiffness.map(_text), st.booleans()).map(
        lambda t: ["vibrations", "planar_3rrr", "--pose=0.02,0.01,0.1",
                   f"--stiffness={t[0]}", *(["--check"] if t[1] else []), "--json"]
    )  # fmt: skip
    duration = st.one_of(
        st.floats(0.001, 0.05),
        numbers().filter(lambda v: not _runs_long(v)),
    )
    gains = st.one_of(
        st.just([]),
        st.lists(numbers(), min_size=2, max_size=2).map(lambda g: [f"--gains={_text(g)}"]),
        st.lists(numbers(), min_size=2, max_size=2).map(lambda g: [f"--tau-zeta={_text(g)}"]),
    )
    sim = st.tuples(_flag("--duration", duration), gains).map(
        lambda t: ["simulate", "rcm_bevel", "--arg", "q3_upper=0.3", t[0], *t[1], "--json"]
    )
    n = st.one_of(st.integers(-5, 6), st.integers(23_861, 10**12))
    track = n.map(lambda k: ["ocp", "track", f"--n={k}", "--json"])
    return st.one_of(vib, sim, track)


def check_fourbar(argv: list[str]) -> str:
    """:func:`check_cli`, and each crank-rocker of ``synthesize`` (the library's roots for
    the same numbers) meets both dead-centre equations: residuals <= 1e-9 (l2 + l3)² [m²]."""
    outcome = check_cli(argv)
    if outcome == "valid" and argv[1] == "synthesize":
        from rcm_pin.linkage.synthesis import synthesize

        v = {a.partition("=")[0][2:]: float(a.partition("=")[2]) for a in argv[2:6]}
        up, down = math.radians(v["up"]), math.radians(v["down"])
        scale = (v["coupler"] + v["rocker"]) ** 2
        valid = [r for r in synthesize(up, down, v["coupler"], v["rocker"]) if r.valid]
        assert valid
        for r in valid:
            assert max(abs(r.residual_up), abs(r.residual_down)) <= 1e-9 * scale
    return outcome


@settings(BOUNDED, max_examples=25)
@given(argv=fourbar_argv())
def test_fourbar_fuzz(argv):
    assert check_fourbar(argv) in ("valid", "typed")


@settings(BOUNDED, max_examples=20, deadline=20_000)
@given(argv=bounds_argv())
def test_bounds_fuzz(argv):
    assert check_cli(argv) in ("valid", "typed")
